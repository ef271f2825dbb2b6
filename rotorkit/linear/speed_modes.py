"""The modes at any swept speed, the eigen-solution a Campbell diagram calls per speed.

:func:`resolve_source` turns what :func:`~rotorkit.linear.campbell.campbell` is given (a linear model, a
system, a model, a preset name or a builder) into a linear model or a system; :func:`speed_solver` gives the
function solving its modes at a speed: from a :class:`~rotorkit.linear.linear_model.LinearModel`, from the
derived symbolic matrices of a linear system evaluated per speed, from one linearisation of a nonlinear
system about the middle of the speed range, or re-linearised at every speed.
"""

from __future__ import annotations

__all__ = ["resolve_source", "speed_solver"]


def resolve_source(source, backend):
    """A System or LinearModel from a System, a Model, a preset name or a builder."""
    from .linear_model import LinearModel

    if isinstance(source, LinearModel):
        return source
    if isinstance(source, str):
        from ..presets import preset

        source = preset(source)
    elif callable(source) and not hasattr(source, "rhs") and not hasattr(source, "compile"):
        source = source()
    if hasattr(source, "rhs") or hasattr(source, "compile"):
        return source  # a model is compiled only if it needs linearising (see speed_solver)
    raise TypeError(
        f"campbell: expected a LinearModel, a System, a Model, a preset name or a function returning one of "
        f"them, got {type(source).__name__}"
    )


def speed_solver(target, speed_parameter, options, n_modes=None, relinearize=False, speeds=None, backend="auto"):
    """(modes_at(speed, vectors=None), spins_at(speed), parameter name) for a LinearModel, a System or a Model.

    ``modes_at(speed, vectors)`` gives every eigenvalue and, where it can
    (a linear model of at most :data:`~rotorkit.linear.modal.DENSE_SIZE` coordinates), the shapes of
    the ``vectors`` lowest modes alone (None: of all).
    """
    from .linear_model import LinearModel, frozen_system, linear_model
    from .modal import DENSE_SIZE, FEW_VECTORS, modes_from_matrices, modes_from_state_matrix, state_matrix

    def sparse_count(n):
        return int(n_modes) + 4 if n_modes is not None and n > DENSE_SIZE else None  # sparse solve for big models

    def dense_modes(state_at, names, positions):
        """modes_at(w, vectors) of a dense state matrix; a speed asked again (more vectors) reuses its eigenvalues."""
        last = {}

        def modes_at(w, vectors=None):
            w = float(w)
            if vectors is not None and vectors > len(names) // FEW_VECTORS:
                vectors = None  # as many as that: every vector at once is cheaper (and certain)
            if last.get("speed") != w:
                last.clear()
                last["speed"], last["A"] = w, state_at(w)
            modes = modes_from_state_matrix(last["A"], names, left=False, n_modes=vectors, sparse=False,
                                            spectrum=last.get("spectrum"), speed=w, station_positions=positions)
            last["spectrum"] = modes.all_eigenvalues
            return modes

        return modes_at

    if isinstance(target, LinearModel):
        wanted = sparse_count(target.n)
        dense_at = dense_modes(target.state_matrix, target.coordinate_names, target.station_positions)

        def linear_modes_at(w, vectors=None):
            if wanted:
                return target.modes(w, left=False, n_modes=wanted)
            return dense_at(w, vectors)

        linear_modes_at.matrices = target.matrices  # dense (M, C, K) at a speed: the refinement's Newton steps
        return linear_modes_at, target.spin_speeds, target.speed_parameter
    from .linear_matrices import linear_evaluator
    from .rotor_speeds import rotor_spin_speeds
    from .station_positions import station_positions
    from .modes import natural_frequencies

    t = options["t"]
    model, speed_parameter = frozen_system(target, speed_parameter, None, t, who="campbell")
    values = model.parameters

    def spins_at(w):
        return rotor_spin_speeds(model, t, dict(values, **{speed_parameter: float(w)}))

    evaluator = None if relinearize else linear_evaluator(model, t, values, free=(speed_parameter,))
    if evaluator is not None:  # linear equations: numbers per speed, no linearisation
        names, positions = tuple(model.coordinate_names), station_positions(model)
        wanted = sparse_count(len(names))

        def matrices_at(w):
            return evaluator.dense(**{speed_parameter: float(w)})

        dense_at = dense_modes(lambda w: state_matrix(*matrices_at(w)), names, positions)

        def modes_at(w, vectors=None):
            if wanted:
                M, C, K = evaluator(**{speed_parameter: float(w)})
                return modes_from_matrices(M, C, K, names, left=False, n_modes=wanted, speed=float(w),
                                           station_positions=positions)
            return dense_at(w, vectors)

        modes_at.matrices = matrices_at
        return modes_at, spins_at, speed_parameter
    source = getattr(target, "model", target)
    system = target if model is source and hasattr(target, "rhs") else model.compile(
        backend=getattr(target, "backend", backend))
    if not relinearize:  # contacts, Hertzian bearings: one linear model about the middle of the range
        middle = 0.5 * (float(speeds[0]) + float(speeds[-1]))
        linear = linear_model(system, speed_parameter=speed_parameter, speed=middle,
                              **{k: v for k, v in options.items() if k != "unbalance"})
        return speed_solver(linear, speed_parameter, options, n_modes)[0], spins_at, speed_parameter

    def relinearized_modes_at(w, vectors=None):
        return natural_frequencies(system.with_parameters(**{speed_parameter: float(w)}), **options)

    return relinearized_modes_at, spins_at, speed_parameter
