"""One speed of a Campbell diagram on the compressor rotor: eigenvalues alone, all vectors, a few vectors.

    PYTHONPATH=. python bench/bench_dense_modes.py [--repeat 25]

The 160 x 160 state matrix of ``examples/compressor.toml`` at 800 rad/s
(warm model cache; one BLAS thread, as ``bench/bench_linear_workflow.py``).
Prints CPU ms per call (minimum and median of ``--repeat``, interleaved so
that a change of the machine's load hits every row alike):

``eig``            :func:`numpy.linalg.eig` (eigenvalues and every vector)
``eigvals``        :func:`numpy.linalg.eigvals` (eigenvalues alone)
``modes, all``     :func:`~rotorkit.linear.modal.modes_from_state_matrix`, every mode's shape
``modes, k``       the same with the shapes of the ``k`` lowest modes alone (eigenvalues
                   plus inverse iteration, :mod:`rotorkit.linear.inverse_iteration`)
``modes, all, left`` every shape and left shape (left ones by inverse iteration, numpy alone)
"""

import argparse
import os
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=25)
    args = parser.parse_args()
    import rotorkit as rk
    from rotorkit.linear.linear_matrices import linear_evaluator
    from rotorkit.linear.linear_model import frozen_system
    from rotorkit.linear.modal import modes_from_state_matrix, state_matrix

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    model = rk.load_model(os.path.join(root, "examples", "compressor.toml"))
    frozen, parameter = frozen_system(model, None, None, 0.0, who="bench")
    evaluator = linear_evaluator(frozen, 0.0, frozen.parameters, free=(parameter,))
    M, C, K = evaluator.dense(**{parameter: 800.0})
    A = state_matrix(M, C, K)
    names = tuple(frozen.coordinate_names)
    cases = {
        "eig": lambda: np.linalg.eig(A),
        "eigvals": lambda: np.linalg.eigvals(A),
        "modes, all": lambda: modes_from_state_matrix(A, names, left=False),
    }
    for k in (6, 8, 12, 16):
        cases[f"modes, {k}"] = (lambda k: lambda: modes_from_state_matrix(A, names, left=False, n_modes=k,
                                                                          sparse=False))(k)
    cases["modes, all, left"] = lambda: modes_from_state_matrix(A, names, mass=M, left=True)
    times = {name: [] for name in cases}
    for _ in range(args.repeat):
        for name, case in cases.items():
            start = time.process_time()
            case()
            times[name].append(time.process_time() - start)
    print(f"state matrix {A.shape[0]} x {A.shape[1]}, CPU ms per call, min and median of {args.repeat}; "
          f"load average {os.getloadavg()[0]:.2f}")
    for name, values in times.items():
        print(f"{name:18s} {1e3 * min(values):8.2f} {1e3 * float(np.median(values)):8.2f}")


if __name__ == "__main__":
    main()
