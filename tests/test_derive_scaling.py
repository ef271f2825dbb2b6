"""The derivation's cost structure: per element, over its own coordinates, each form derived once."""

import sympy as sp

import rotorkit as rk
from rotorkit.symbolic import lagrange


def chain(n, reverse=False):
    """A chain of eccentric disks; ``reverse`` writes every other segment end-to-start."""
    elements = [rk.Rotor(name="R", stations=tuple(range(n)), speed=100.0)]
    elements += [rk.Disk(station=i, mass=1.0 + i, radius=0.1, eccentricity=1e-5, torsion=(i == 1)) for i in range(n)]
    for i in range(n - 1):
        a, b = (i + 1, i) if reverse and i % 2 else (i, i + 1)
        elements.append(rk.ShaftSegment(start=a, end=b, bending_stiffness=1e5, bending_damping=1.0,
                                        torsional_stiffness=100.0 if 1 in (a, b) else None))
    elements += [rk.ElasticSupport(station=0, stiffness=1e5), rk.ElasticSupport(station=n - 1, stiffness=1e5),
                 rk.RubStator(station=n // 2, clearance=1e-4, contact_stiffness=1e6, friction_coefficient=0.2)]
    return rk.Model(elements)


def derive_fresh(model, share=True, monkeypatch=None):
    lagrange._CACHE.clear()
    if not share:  # every element derived on its own: the reference for the shared derivation
        monkeypatch.setattr(lagrange._Templates, "done", property(lambda self: {}, lambda self, v: None), raising=False)
    eom = lagrange.derive(model)
    lagrange._CACHE.clear()
    if not share:
        monkeypatch.undo()
    return eom


def test_shared_derivations_equal_element_by_element_derivation(monkeypatch):
    """Renaming a derived template gives exactly what deriving each element gives (reversed segments,
    torsion and a rub contact included)."""
    model = chain(6, reverse=True)
    shared = derive_fresh(model)
    single = derive_fresh(model, share=False, monkeypatch=monkeypatch)
    for name in ("mass_matrix", "forcing", "stiffness", "damping", "loads", "kinetic", "potential", "switches"):
        assert getattr(shared, name) == getattr(single, name), name
    assert shared.forces.keys() == single.forces.keys()
    assert all(shared.forces[k] == single.forces[k] for k in shared.forces)
    # and it is not vacuous: the chain's matrices couple neighbours and hold every disk's mass
    M, K = shared.mass_matrix, shared.stiffness
    x2, x3 = shared.coordinates.index(sp.Symbol("x2", real=True)), shared.coordinates.index(sp.Symbol("x3", real=True))
    assert K[x2, x3] != 0 and K[x2, x3 + 1] == 0
    assert M[x3, x3] == sp.Symbol("disk3_mass", real=True)


def test_number_of_derivations_does_not_grow_with_the_chain(monkeypatch):
    """Each element form is differentiated once: a chain 4x longer does no more symbolic derivation."""
    calls = []
    original = lagrange._element_contribution

    def counting(*args):
        calls.append(1)
        return original(*args)

    monkeypatch.setattr(lagrange, "_element_contribution", counting)
    counts = []
    for n in (6, 24):
        calls.clear()
        eom = derive_fresh(chain(n))
        counts.append(len(calls))
        assert eom.n == 2 * n + 1
    assert counts[0] == counts[1] <= 12


def test_matrices_are_sparse():
    """Large models store only the non-zero entries of M, K and C."""
    eom = derive_fresh(chain(40))
    assert isinstance(eom.mass_matrix, sp.ImmutableSparseMatrix)
    assert len(eom.stiffness.todok()) < 6 * eom.n
