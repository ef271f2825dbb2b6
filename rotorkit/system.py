"""The compiled numeric system: ``rhs(t, y)`` in scipy's ``fun(t, y)`` form."""

import copy
import os

import numpy as np

from .errors import ParameterError

__all__ = ["System", "compile_model", "available_backends", "jacobian_module"]

BACKENDS = ("python", "numba", "c")
#: back ends whose right-hand side runs in the compiled integration loop
COMPILED_BACKENDS = ("numba", "c")
#: what ``backend="auto"`` picks, first available first (``c`` only for unrolled code generation)
AUTO_ORDER = ("c", "numba", "python")


def available_backends():
    """The back ends usable here: ``python`` always, ``numba`` when installed, ``c`` when a C compiler is found."""
    import importlib.util
    import sys

    from .codegen.cbuild import compiler

    found = ["python"]
    # find, not import: numba's import costs a quarter second (None in sys.modules: blocked, as by the tests)
    if sys.modules["numba"] is not None if "numba" in sys.modules else importlib.util.find_spec("numba") is not None:
        found.append("numba")
    if compiler() is not None:
        found.append("c")
    return tuple(found)


def resolve_backend(backend, c_ok=True):
    """The back end to use for ``backend`` (``auto``: $ROTORKIT_BACKEND, else the first of AUTO_ORDER available).

    ``c_ok=False`` (code the C translation does not cover: structured or reduced models) turns an automatic
    ``c`` into numba (or python).
    """
    requested = backend
    if backend == "auto":
        backend = os.environ.get("ROTORKIT_BACKEND", "auto")
    if backend not in BACKENDS + ("auto",):
        raise ParameterError(f"backend={backend!r} is unknown; expected 'auto', 'python', 'numba' or 'c'")
    available = available_backends()
    if backend == "auto":
        return next(b for b in AUTO_ORDER if b in available and (c_ok or b != "c"))
    if backend not in available:
        fix = ("pip install 'rotorkit[fast]'" if backend == "numba"
               else "install a C compiler (gcc) or set $CC; ROTORKIT_C_COMPILER=0 disables it")
        raise ParameterError(f"backend={backend!r} is not available here: {fix} (or use backend='python')")
    if backend == "c" and not c_ok:
        if requested == "auto":  # $ROTORKIT_BACKEND=c asks for C where it can be had
            return next(b for b in AUTO_ORDER[1:] if b in available)
        raise ParameterError("backend='c' covers unrolled code generation only (this model is generated as matrices, "
                             "codegen='structured', or reduced); use backend='numba' or 'auto'")
    return backend


class System:
    """A compiled model: numbers in, derivatives out.

    Attributes
    ----------
    state_names : tuple of str
        Coordinates in order, then their velocities (``x2``, ..., ``x2_dot``, ...).
    coordinate_names : tuple of str
    parameters : dict
        Parameter name -> SI value (a copy).
    time_events : tuple of float
        Times (s) at which the equations jump (manoeuvre start/end); the
        simulation restarts there.
    backend : str
        ``"python"``, ``"numba"`` or ``"c"``.
    core : callable
        ``core(t, y, p, dydt)``: the generated function (numba-compiled for
        the numba back end, a :class:`~rotorkit.codegen.cmodel.CFunction`
        for the c back end) taking the prepared parameter vector ``p``.
    prepared_parameters : numpy.ndarray
        Parameters followed by the parameter-only subexpressions.
    """

    def __init__(self, model, module, backend, core):
        self.model = model
        self.name = model.name
        self.structure_key = model.structure_key
        self.backend = backend
        self.core = core
        self._module = module
        self.parameter_names = tuple(module.PARAMETER_NAMES)
        self.state_names = tuple(module.STATE_NAMES)
        self.coordinate_names = self.state_names[: module.N_COORDINATES]
        self._values = model.parameters
        values = self._run_values = self._with_runtime_values(model, module)
        p = np.array([values[n] for n in self.parameter_names], dtype=float)
        with np.errstate(all="ignore"):
            prepared = module.prepare(p, np.empty(module.N_PREPARED))
        bad = np.flatnonzero(~np.isfinite(prepared[: len(p) + module.N_DERIVED]))
        if not bad.size and not np.all(np.isfinite(prepared[:-2])):  # structured code: M0 and its inverse
            raise ParameterError(
                f"{self.name}: the parameters give a constant mass matrix that is not finite and positive definite "
                "(a mass, density or length zero or negative?)"
            )
        if bad.size:
            culprits = sorted({n for k in bad - len(p) for n in module.DERIVED_PARAMETERS[k]})
            raise ParameterError(
                f"{self.name}: the parameters {', '.join(culprits)} = "
                f"{', '.join(f'{values[n]:g}' for n in culprits)} give non-finite derived values "
                "(a length or mass too close to zero, or a value too large: a speed or stiffness beyond "
                "about 1e150 overflows its square)"
            )
        self.prepared_parameters = prepared
        self._plist = prepared.tolist()
        self._jacobian_parts = {}  # shared by the within() copies: same parameters

    def _with_runtime_values(self, model, module):
        """The parameter values, with those of the run-time parameters a generated module may append.

        Only a model with ``Rotor(damping=ModalDamping(...))`` has any: the
        entries of its modal damping matrix, computed here once per parameter
        set (:func:`rotorkit.linear.modal_damping.runtime_values`); for every
        other model this is ``model.parameters`` itself.
        """
        n = getattr(module, "N_MODAL_DAMPING", 0)
        if not n:
            return self._values
        from .linear.modal_damping import runtime_values

        names = tuple(module.PARAMETER_NAMES)[-n:]
        return {**self._values, **runtime_values(model, names, self.coordinate_names)}

    def parameter_vector(self, names):
        """The values (SI floats, shape (len(names),)) of ``names``: parameters, and the run-time ones of a
        generated module (a ModalDamping's matrix entries), for a module's ``prepare(p, out)``."""
        return np.array([self._run_values[n] for n in names], dtype=float)

    @property
    def modal_damping(self):
        """Whether the equations hold a rotor's :class:`~rotorkit.elements.damping.ModalDamping` (``-C q'``)."""
        return bool(getattr(self._module, "N_MODAL_DAMPING", 0))

    @property
    def has_jacobian(self):
        """Whether the analytic Jacobian is available (True for generated systems).

        It is generated on first use (:meth:`jacobian`), in a module of its
        own: explicit runs, which never need it, do not pay for it.
        """
        return bool(getattr(self._module, "HAS_JACOBIAN", False)) or hasattr(self, "_jacobian_parts")

    def _jacobian_function(self):
        """(module, prepared vector, the same as a list) for the generated ``jac`` under this time window."""
        if getattr(self._module, "HAS_JACOBIAN", False):  # a module generated with its Jacobian
            return self._module, self.prepared_parameters, self._plist
        parts = self._jacobian_parts
        if "module" not in parts:
            module = jacobian_module(self.model, self._module.CODEGEN)
            p = self.parameter_vector(module.PARAMETER_NAMES)
            with np.errstate(all="ignore"):
                parts["prepared"] = module.prepare(p, np.empty(module.N_PREPARED))
            parts["module"], parts["windows"] = module, {}
        window = (float(self.prepared_parameters[-2]), float(self.prepared_parameters[-1]))
        found = parts["windows"].get(window)
        if found is None:
            prepared = parts["prepared"].copy()
            prepared[-2:] = window
            if len(parts["windows"]) > 64:
                parts["windows"].clear()
            found = parts["windows"][window] = (prepared, prepared.tolist())
        return (parts["module"],) + found

    @property
    def n_states(self):
        return len(self.state_names)

    @property
    def parameters(self):
        return dict(self._values)

    @property
    def time_events(self):
        times = [self._values[n] for n in self.model.time_event_parameters()] + list(self.model.fixed_time_events())
        return tuple(sorted(set(times)))

    def state_index(self, name):
        """Index of a state by name, with a clear error for unknown names."""
        try:
            return self.state_names.index(name)
        except ValueError:
            import difflib

            near = difflib.get_close_matches(name, self.state_names, n=3)
            hint = f"; did you mean {', '.join(near)}?" if near else ""
            raise ParameterError(f"unknown state {name!r}{hint} (states: {', '.join(self.state_names)})") from None

    def rhs(self, t, y):
        """dy/dt at time ``t`` (s) and state ``y`` (shape (n_states,)), scipy's ``fun(t, y)``."""
        if self.backend in COMPILED_BACKENDS:
            dydt = np.empty(self.n_states)
            self.core(float(t), _state(y), self.prepared_parameters, dydt)
            return dydt
        dydt = [0.0] * self.n_states
        self.core(float(t), np.asarray(y, dtype=float).tolist(), self._plist, dydt)
        return np.array(dydt)

    def jacobian(self, t, y, compiled=None):
        """The analytic Jacobian d(dy/dt)/dy, shape (n_states, n_states), from the symbolic equations.

        Contact kinks are differentiated one-sidedly (the step of a ramp is 0
        at the kink). Used by the implicit methods (Radau, BDF, LSODA).
        ``compiled=False`` evaluates the plain-Python version (no numba
        compilation: right for a single evaluation).
        """
        module, prepared, plist = self._jacobian_function()
        J = np.zeros((self.n_states, self.n_states))
        if compiled is None:
            compiled = self.backend in COMPILED_BACKENDS
        if compiled:
            _compiled_function(module, "jac", self.backend)(float(t), _state(y), prepared, J)
        else:
            module.jac(float(t), np.asarray(y, dtype=float).tolist(), plist, J)
        return J

    @property
    def n_switches(self):
        """Number of contact switch functions (see :meth:`switch_values`)."""
        return int(getattr(self._module, "N_SWITCHES", 0))

    def switch_values(self, t, y):
        """The elements' switch functions g(t, y): contact onset/loss where one changes sign."""
        out = np.zeros(self.n_switches)
        if self.backend in COMPILED_BACKENDS:
            _compiled_function(self._module, "switches", self.backend)(float(t), _state(y), self.prepared_parameters,
                                                                       out)
        else:
            self._module.switches(float(t), np.asarray(y, dtype=float).tolist(), self._plist, out)
        return out

    def within(self, start, end):
        """A copy whose equations see time clamped just inside ``[start, end]``.

        Used per integration segment between time discontinuities: at the
        segment's ends the equations take their values from inside it.
        """
        view = copy.copy(self)
        prepared = self.prepared_parameters.copy()
        prepared[-2], prepared[-1] = np.nextafter(start, end), np.nextafter(end, start)
        view.prepared_parameters = prepared
        view._plist = prepared.tolist()
        return view

    def with_parameters(self, **overrides):
        """A copy with some parameter values changed (no re-derivation, no recompilation).

        Values are SI floats or pint quantities; names as in :attr:`parameters`.
        Each value is checked by its element (units, sign, cross-field rules).
        """
        changed = System(self.model.with_values(**overrides), self._module, self.backend, self.core)
        window = self.prepared_parameters[-2:]
        if window[0] > -1e300 or window[1] < 1e300:  # keep a time window set by within()
            return changed.within(np.nextafter(window[0], -np.inf), np.nextafter(window[1], np.inf))
        return changed

    def initial_state(self, **values):
        """A state vector of zeros with some named entries set (``x2=1e-4``)."""
        from .units import to_si

        y = np.zeros(self.n_states)
        for name, v in values.items():
            index = self.state_index(name)
            y[index] = to_si(v, "", name) if not hasattr(v, "magnitude") else float(v.to_base_units().magnitude)
        return y

    def __repr__(self):
        return f"System({self.name!r}, {self.n_states} states, {len(self.parameter_names)} parameters, backend={self.backend!r})"


_JIT_CACHE = {}


def _state(y):
    return np.ascontiguousarray(y, dtype=float)


def _compiled_function(module, name, backend):
    """The generated function ``name`` of ``module`` compiled by ``backend`` (``numba`` or ``c``)."""
    if backend == "c":
        from .codegen.cmodel import c_functions

        return c_functions(module)[name]
    return numba_function(module, name)


def numba_function(module, name):
    func = _JIT_CACHE.get((module.__name__, name))
    if func is None:
        from .codegen import cache

        func = cache.jit(module, name, error_model="numpy")  # numba's disk cache verified (codegen/cache.py)
        _JIT_CACHE[(module.__name__, name)] = func
    return func


def compile_model(model, backend="auto", codegen="auto"):
    """Derive (once per structure), generate and load the RHS of ``model``.

    The generated module is cached on disk by the model's structure
    (:mod:`rotorkit.codegen.cache`): a warm start derives nothing.

    Parameters
    ----------
    model : rotorkit.Model
    backend : {"auto", "c", "numba", "python"}
        ``c`` translates the generated code to C and builds it with the
        machine's C compiler (fast to build and to load: the quick start);
        ``numba`` compiles it with numba; ``python`` runs it as is. ``auto``
        (``$ROTORKIT_BACKEND`` overrides) picks ``c`` when a compiler is
        found and the code is unrolled, else ``numba`` when installed, else
        ``python``; a C build that fails falls back to numba with a warning.
    codegen : {"auto", "unrolled", "structured"}
        How the right-hand side is generated (:func:`rotorkit.codegen.generate.generate`):
        ``auto`` (``$ROTORKIT_CODEGEN`` overrides) unrolls small models and
        gives large ones matrices for the linear part. Both give the same
        numbers (to rounding); each is cached on its own.

    Returns
    -------
    System
    """
    from .codegen import codegen_mode

    mode = codegen_mode(len(model.coordinate_names), codegen)
    automatic = backend == "auto" and os.environ.get("ROTORKIT_BACKEND", "auto") == "auto"
    backend = resolve_backend(backend, c_ok=mode == "unrolled")
    module = _generated(model, mode, jacobian=False)
    if backend == "c":
        core = _c_core(model, module, fall_back=automatic)
        if core is not None:
            return System(model, module, backend, core)
        backend = resolve_backend("auto", c_ok=False)
    if backend == "numba":
        core = numba_function(module, "rhs")
        if not core.signatures:  # compile now, with a notice if slow, not silently inside the first run
            from .engines.rk_numba import CORE_SIGNATURE
            from .progress import announce_if_slow

            with announce_if_slow(f"compiling {model.name} with numba (first use in this process; numba caches "
                                  "the machine code on disk)"):
                core.compile(CORE_SIGNATURE.args)
    else:
        core = module.rhs
    return System(model, module, backend, core)


def _c_core(model, module, fall_back):
    """The C right-hand side of ``module``; None (with a warning) if it cannot be built and ``fall_back``."""
    import warnings

    from .codegen.cbuild import CompilerError
    from .codegen.cmodel import c_functions
    from .codegen.csource import Untranslatable
    from .progress import announce_if_slow

    try:
        with announce_if_slow(f"compiling {model.name} with the C compiler (first use; cached on disk)"):
            return c_functions(module)["rhs"]
    except (CompilerError, Untranslatable, OSError) as exc:
        if not fall_back:
            raise
        warnings.warn(f"{model.name}: the c back end failed ({exc}); using {resolve_backend('auto', c_ok=False)}",
                      RuntimeWarning, stacklevel=4)
        return None


_MODULES = {}


def jacobian_module(model, codegen):
    """The generated module holding ``jac`` for ``model`` (``codegen``: ``'unrolled'`` or ``'structured'``).

    Generated on first use and cached on disk under ``<structure key>_jac``
    (``<structure key>_structured_jac``): the right-hand side's module holds
    no Jacobian, whose derivatives and common subexpressions cost about as
    much to generate again as the right-hand side itself. This module has
    its own prepared-parameter layout (:meth:`System._jacobian_function`).
    """
    return _generated(model, codegen, jacobian=True)


def _generated(model, mode, jacobian):
    """The generated module of ``model`` in codegen ``mode``: the right-hand side's, or with ``jacobian`` the
    Jacobian's; from this process, else from the disk cache, else generated now and stored there."""
    from .codegen import cache

    modal = _has_modal_damping(model)
    key = (model.structure_key + ("_modal" if modal else "") + ("" if mode == "unrolled" else "_structured")
           + ("_jac" if jacobian else ""))
    module = _MODULES.get(key) or cache.load(key)
    if module is None:
        from .codegen.generate import generate
        from .progress import announce_if_slow

        eom = model.equations()
        n_before = len(eom.parameters)
        if modal:  # -C q' with C's entries as run-time parameters (System fills them)
            from .linear.modal_damping import with_modal_damping

            eom = with_modal_damping(eom, model)
        what = (f"the analytic Jacobian of {model.name} (first use" if jacobian
                else f"code for {model.name} (first use of this model structure")
        with announce_if_slow(f"generating {what}; cached on disk afterwards)"):
            source = generate(eom, key, jacobian=jacobian, mode=mode).source
            if modal:
                source += f"N_MODAL_DAMPING = {len(eom.parameters) - n_before}\n"
            module = cache.store(key, source)
    _MODULES[key] = module
    return module


def _has_modal_damping(model):
    """Whether a rotor of ``model`` holds a ModalDamping (duck-typed, as ``linear_matrices.modal_damping_spec``)."""
    return any(hasattr(getattr(r, "damping", None), "ratios") for r in model.rotors.values())
