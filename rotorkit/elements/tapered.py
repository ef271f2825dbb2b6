"""Tapered shaft segments: Timoshenko beam elements whose diameters vary linearly along the axis.

A :class:`TaperedBeamSegment` is a :class:`~rotorkit.elements.beam.BeamSegment`
whose outer and inner diameters go linearly from their values at ``start``
to ``outer_diameter_end``, ``inner_diameter_end`` at ``end``. Each of its
``elements`` finite elements is tapered too (the diameters at its nodes lie
on the same lines).

Element matrices (per bending plane, over ``(w1, beta1, w2, beta2)``, with
``s = z / l`` along an element of length ``l``): the section properties are
polynomials in ``s``, ``A(s) = sum_k A_k s^k`` (quadratic) and
``I(s) = sum_k I_k s^k`` (quartic), and the energies of the module
:mod:`rotorkit.elements.beam` are integrated exactly with them::

    K = E sum_k I_k int s^k N_beta'^T N_beta' dz + E I_m S          (bending + shear)
    M = rho sum_k A_k int s^k N_w^T N_w dz + rho sum_k I_k int s^k N_beta^T N_beta dz
    G: rho I_p(s) = 2 rho I(s) in the gyroscopic integral, likewise

where ``S`` is the shear block of the uniform element per ``EI`` and the
shape functions are the uniform element's with
``phi = 12 E I_m / (kappa G A_m l^2)`` of the *mean* section
(``A_m = int A ds``, ``I_m = int I ds``; ``kappa`` Cowper's for the mid-element
diameter ratio unless given). This is a Rayleigh-Ritz element: exact in
mass, bending and gyroscopic integrals for the Euler-Bernoulli beam
(``phi = 0``, Hermite cubics), with the shear energy of the mean section;
it converges to the tapered beam as the mesh is refined, and for equal end
diameters it is the uniform element. With shear the shape functions keep the
uniform element's tie between shear strain and curvature (the mean
section's), so the Timoshenko element converges more slowly, about first
order in the element length (a solid 80-to-40 mm cone cantilever, 1 m: the
first frequency 0.15 % above the converged value with 8 elements, 0.02 %
with 32); the Euler-Bernoulli element converges as the uniform one. Torsion (``torsion=True``) uses linear
shape functions with ``G I_p(s)`` and ``rho I_p(s)`` integrated exactly.

The geometric stiffness of an axial force (``axial_force``) is the uniform
element's (the force is constant along the segment).

Verification (``tests/test_tapered.py``): a fine discretisation into uniform
stepped elements, an independent shooting solution of the Euler-Bernoulli
equation of a truncated cone, and Kirchhoff's complete-cone cantilever
``w_1 = 8.719 / L^2 sqrt(E I_0 / (rho A_0))`` (base section; Blevins,
*Formulas for Natural Frequency and Mode Shape*, table 8-8).
"""

import functools
import math
from dataclasses import dataclass

from ..errors import ParameterError
from .base import QuadraticForm, Terms
from .base_motion import base_frame
from .beam import BeamSegment, cowper_shear_coefficient, plane_template, shape_functions

__all__ = ["TaperedBeamSegment", "tapered_moments"]

_FORMS = {}  # structural variant -> element matrices in placeholder symbols


@functools.cache
def tapered_moments():
    """Moment matrices ``int_0^l (z/l)^k X dz`` of the shape-function products (sympy, cached).

    Returns
    -------
    dict
        ``"bending"`` (k = 0..4): ``N_beta'^T N_beta'``; ``"translational"``
        (k = 0..2): ``N_w^T N_w``; ``"rotary"`` (k = 0..4): ``N_beta^T N_beta``;
        each a list of 4x4 matrices rational in ``l`` and ``phi`` (the symbols
        of :func:`~rotorkit.elements.beam.plane_template`); ``"shear"``, the
        uniform element's shear block per ``EI``; ``"rotary_vector"``
        (k = 0..4): ``N_beta^T``, 4x1.
    """
    import sympy as sp

    z, l, phi, Nw, Nb = shape_functions()
    s = sp.Symbol("s")

    def in_s(row):  # entries as (numerator polynomial in s, denominator) with z = l s
        return [sp.fraction(sp.cancel(e.subs(z, l * s))) for e in row]

    def moments(left, right, kmax):
        out = []
        for k in range(kmax + 1):
            X = sp.zeros(4, 4)
            for i, (ni, di) in enumerate(left):
                for j, (nj, dj) in enumerate(right):
                    poly = sp.Poly(sp.expand(ni * nj * s**k), s)
                    value = sum(c / (m + 1) for (m,), c in poly.terms())  # int_0^1 ds
                    X[i, j] = sp.factor(l * value) / (di * dj)  # dz = l ds
            out.append(X)
        return out

    Nw_s, Nb_s = in_s(Nw), in_s(Nb)
    dNb_s = in_s(sp.diff(Nb, z))
    bending = moments(dNb_s, dNb_s, 4)
    vector = []  # int s^k N_beta^T dz, 4x1
    for k in range(5):
        column = sp.zeros(4, 1)
        for i, (ni, di) in enumerate(Nb_s):
            poly = sp.Poly(sp.expand(ni * s**k), s)
            column[i] = sp.factor(l * sum(c / (m + 1) for (m,), c in poly.terms())) / di
        vector.append(column)
    shear = (plane_template()["stiffness"] - bending[0]).applyfunc(sp.factor)
    return {"bending": bending, "translational": moments(Nw_s, Nw_s, 2), "rotary": moments(Nb_s, Nb_s, 4),
            "shear": shear, "rotary_vector": vector}


@functools.cache
def _phi_powers(kind):
    """Per entry of each moment matrix of ``kind``: ``{m: c_m(l)}`` with ``X = sum_m c_m phi^m / (1 + phi)^2``."""
    import sympy as sp

    _, _, phi, _, _ = shape_functions()
    moments = tapered_moments()
    matrices = moments["bending"] + [moments["shear"]] if kind == "stiffness" else moments[kind]
    out = []
    for X in matrices:
        entries = {}
        for i in range(4):
            for j in range(4):
                numerator = sp.expand(sp.cancel(X[i, j] * (1 + phi) ** 2))
                entries[i, j] = {m: a for (m,), a in sp.Poly(numerator, phi).terms()}
        out.append(entries)
    return out


@dataclass(frozen=True, slots=True, kw_only=True)
class TaperedBeamSegment(BeamSegment):
    """A shaft segment whose outer and inner diameters vary linearly from ``start`` to ``end``.

    It takes the parameters of :class:`~rotorkit.elements.beam.BeamSegment`
    (``outer_diameter`` and ``inner_diameter`` are the diameters at
    ``start``) and the two below. See the module docstring for the element
    matrices and their verification. In a turning base
    (:class:`~rotorkit.elements.base_motion.BaseRotation`) its loads are the
    uniform segment's with the tapered element's mass and section-inertia
    integrals.

    Parameters
    ----------
    outer_diameter_end : float or pint.Quantity
        d_o at ``end`` (m), > 0.
    inner_diameter_end : float or pint.Quantity, optional
        d_i at ``end`` (m), 0 <= d_i < d_o; default ``inner_diameter``.

    Examples
    --------
    >>> from rotorkit.elements import Material
    >>> b = TaperedBeamSegment(start=1, end=2, length=0.3, outer_diameter=0.06, outer_diameter_end=0.04,
    ...                        material=Material.steel())
    >>> round(b.mass_value(), 3)  # rho pi L (d0^2 + d0 d1 + d1^2) / 12
    4.662
    >>> TaperedBeamSegment.from_taper(start=1, end=2, length=0.3, outer_diameter=0.06, outer_taper=-0.25,
    ...                               material=Material.steel())  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    rotorkit.errors.ParameterError: ... outer_taper = -0.25 over length = 0.3 m gives an outer diameter of -0.015 m ...
    """

    outer_diameter_end: float = None
    inner_diameter_end: float | None = None

    _units = {**BeamSegment._units, "outer_diameter_end": ("m", "positive"),
              "inner_diameter_end": ("m", "nonnegative")}
    _latex_names = {**BeamSegment._latex_names, "outer_diameter_end": "d_{o,e}", "inner_diameter_end": "d_{i,e}"}

    @classmethod
    def from_taper(cls, *, start, end, length, outer_diameter, outer_taper=0.0, inner_diameter=0.0,
                   inner_taper=0.0, **kwargs):
        """A segment from the diameters at ``start`` and their tapers ``d(d)/dz`` (m/m, SI floats).

        ``outer_taper = -0.02`` shrinks the outer diameter by 2 cm per metre
        of length. A taper that makes a diameter negative (or the outer one
        zero) at the end is a :class:`~rotorkit.errors.ParameterError`.
        """
        from ..units import to_si

        who = f"TaperedBeamSegment.from_taper {start!r}-{end!r}"
        length_si = to_si(length, "m", f"{who}: length", sign="positive")
        do = to_si(outer_diameter, "m", f"{who}: outer_diameter", sign="positive")
        di = to_si(inner_diameter, "m", f"{who}: inner_diameter", sign="nonnegative")
        ends = {}
        for name, d0, taper, rule in (("outer", do, outer_taper, "> 0"), ("inner", di, inner_taper, ">= 0")):
            taper = to_si(taper, "", f"{who}: {name}_taper")
            d1 = d0 + taper * length_si
            if d1 < 0 or (name == "outer" and d1 <= 0):
                raise ParameterError(f"{who}: {name}_taper = {taper:g} over length = {length_si:g} m gives an "
                                     f"{name} diameter of {d1:.6g} m at the end; expected a taper that keeps it "
                                     f"{rule}")
            ends[name] = d1
        return cls(start=start, end=end, length=length_si, outer_diameter=do, inner_diameter=di,
                   outer_diameter_end=ends["outer"], inner_diameter_end=ends["inner"], **kwargs)

    def _validate(self):
        who = f"TaperedBeamSegment {self.start!r}-{self.end!r}"
        if self.torque is not None:
            raise ParameterError(f"{who}: torque = {self.torque!r}: an axial torque is available on BeamSegment "
                                 "only; split the taper into uniform BeamSegments to carry a torque")
        if self.outer_diameter_end is None:
            raise ParameterError(f"{who}: outer_diameter_end is required (m, > 0); for a uniform shaft use "
                                 "BeamSegment")
        if self.inner_diameter_end is None:
            object.__setattr__(self, "inner_diameter_end", self.inner_diameter)
        BeamSegment._validate(self)
        if not self.inner_diameter_end < self.outer_diameter_end:
            raise ParameterError(f"{who}: inner_diameter_end = {self.inner_diameter_end:g} m must be smaller than "
                                 f"outer_diameter_end = {self.outer_diameter_end:g} m")

    def _default_label(self):
        return f"taperedbeam{self.start}_{self.end}"

    def _solid(self):
        return self.inner_diameter == 0 and self.inner_diameter_end == 0

    # -- values -----------------------------------------------------------
    def mass_value(self):
        """Mass of the segment (kg): ``rho pi L / 12 [(a0^2 + a0 a1 + a1^2) - (b0^2 + b0 b1 + b1^2)]``."""
        a0, a1, b0, b1 = self.outer_diameter, self.outer_diameter_end, self.inner_diameter, self.inner_diameter_end
        return self.density * math.pi * self.length / 12 * ((a0**2 + a0 * a1 + a1**2) - (b0**2 + b0 * b1 + b1**2))

    def _node_diameters(self, p, k):
        """(d_o, d_i) at node ``k`` (0..elements) as expressions of the parameter symbols ``p``."""
        f = k / self.elements
        do = p["outer_diameter"] + (p["outer_diameter_end"] - p["outer_diameter"]) * f
        if self._solid():
            return do, 0
        return do, p["inner_diameter"] + (p["inner_diameter_end"] - p["inner_diameter"]) * f

    def _tapered_element(self, q):
        """(K, M, Mr, I_mean, Ik, (M_t, R)) of one plane from placeholder symbols ``q``.

        ``q`` holds ``do_a, do_b, di_a, di_b`` (node diameters), ``density``,
        ``youngs_modulus``, ``shear_modulus``, ``shear_coefficient``, ``l`` and
        ``axial_force``. ``Mr`` is the rotary integral per unit ``rho``
        (``int I(s) N_beta^T N_beta dz``), ``M_t`` the translational mass and
        ``R = int I(s) N_beta^T dz`` (for a turning base); ``Ik`` the coefficients of ``I(s) = sum_k Ik[k] s^k``
        (``s`` from 0 to 1 along the element; the torsion's ``I_p(s) = 2 I(s)``).
        """
        import sympy as sp

        # d(s) = a + (b - a) s: d^n = sum_k C(n, k) a^(n-k) (b - a)^k s^k, kept unexpanded (compact expressions)
        def power_coefficients(a, b, n):
            return [math.comb(n, k) * a ** (n - k) * (b - a) ** k for k in range(n + 1)]

        oa, ob, ia, ib = q["do_a"], q["do_b"], q["di_a"], q["di_b"]
        Ak = [sp.pi / 4 * (x - y) for x, y in zip(power_coefficients(oa, ob, 2), power_coefficients(ia, ib, 2))]
        Ik = [sp.pi / 64 * (x - y) for x, y in zip(power_coefficients(oa, ob, 4), power_coefficients(ia, ib, 4))]
        # means over the element: int_0^1 (a + (b - a) s)^n ds = (a^n + a^(n-1) b + ... + b^n) / (n + 1)
        def mean_power(a, b, n):
            return sum(a ** (n - k) * b**k for k in range(n + 1)) / (n + 1)

        A_mean = sp.pi / 4 * (mean_power(oa, ob, 2) - mean_power(ia, ib, 2))
        I_mean = sp.pi / 64 * (mean_power(oa, ob, 4) - mean_power(ia, ib, 4))
        rho, E, G, l = q["density"], q["youngs_modulus"], q["shear_modulus"], q["l"]
        tpl = plane_template()
        l_sym, phi_sym = tpl["symbols"]
        if self.theory == "timoshenko":
            if self.shear_coefficient is not None:
                kappa = q["shear_coefficient"]
            else:
                ratio = (q["di_a"] + q["di_b"]) / (q["do_a"] + q["do_b"]) if not self._solid() else 0
                kappa = cowper_shear_coefficient(E / (2 * G) - 1, ratio)
            phi = 12 * E * I_mean / (kappa * G * A_mean * l**2)
        else:
            phi = sp.S.Zero
        subs = {l_sym: l, phi_sym: phi}

        def combine(coefficients, kind):
            """sum_k c_k X_k(l, phi) as ``(n0 + phi (n1 + phi n2)) / (1 + phi)^2`` per entry: phi (an
            expression of the element's diameters) appears three times, not three times per term."""
            out = sp.zeros(4, 4)
            for (i, j), _ in _phi_powers(kind)[0].items():
                powers = {}
                for c, X in zip(coefficients, _phi_powers(kind)):
                    for m, a in X[i, j].items():
                        powers.setdefault(m, []).append(c * a)
                horner = sp.S.Zero
                for m in range(max(powers, default=0), -1, -1):
                    horner = horner * phi_sym + sp.Add(*powers.get(m, ()))
                out[i, j] = horner / (1 + phi_sym) ** 2
            return out.xreplace(subs)

        K = E * combine(Ik + [I_mean], "stiffness")
        if self.axial_force is not None:
            K = K + q["axial_force"] * tpl["geometric"].xreplace(subs)
        Mr = combine(Ik, "rotary")
        Mt = rho * combine(Ak, "translational")
        M = Mt + rho * Mr if self.rotary_inertia else Mt
        R = sum((c * v for c, v in zip(Ik, tapered_moments()["rotary_vector"])), sp.zeros(4, 1)).xreplace(subs)
        return K, M, Mr, I_mean, Ik, (Mt, R)

    def _forms_template(self):
        """(placeholders, spin, mass, stiffness, gyroscopic, torsion) 8x8 (and 2x2) of one element."""
        import sympy as sp

        key = (self.theory, self.rotary_inertia, self.gyroscopic, self._solid(), self.shear_coefficient is None,
               self.axial_force is not None, self.torsion)
        cached = _FORMS.get(key)
        if cached is None:
            names = ("do_a", "do_b", "di_a", "di_b", "density", "youngs_modulus", "shear_modulus",
                     "shear_coefficient", "l", "axial_force")
            q = {n: sp.Symbol(f"_taper_{n}", real=True) for n in names}
            if self._solid():
                q["di_a"] = q["di_b"] = sp.S.Zero
            spin = sp.Symbol("_taper_spin", real=True)
            K, M, Mr, I_mean, Ik, (Mt, R) = self._tapered_element(q)
            sign = sp.diag(1, -1, 1, -1)  # y-z plane: (w, beta) = (y, -thx)
            Z = sp.zeros(4, 4)
            mass = sp.ImmutableMatrix(sp.BlockMatrix([[M, Z], [Z, sign * M * sign]]))
            stiffness = sp.ImmutableMatrix(sp.BlockMatrix([[K, Z], [Z, sign * K * sign]]))
            gyro = None
            if self.gyroscopic:  # as BeamSegment, with rho I_p(s) = 2 rho I(s) inside the integral
                gyro = sp.zeros(8, 8)
                gyro[4:, :4] = -spin * 2 * q["density"] * (sign * Mr)
                gyro = sp.ImmutableMatrix(gyro)
            torsion = None
            if self.torsion:  # linear shape functions (1 - s, s); int s^k (1-s)^a s^b ds = Beta functions
                l = q["l"]
                mt = sp.zeros(2, 2)
                for i in range(2):
                    for j in range(2):
                        # int_0^1 s^k N_i N_j ds with N_0 = 1 - s, N_1 = s
                        e = sum(c * _shape_moment(k, i, j) for k, c in enumerate(Ik))
                        mt[i, j] = 2 * q["density"] * l * e
                gip = 2 * q["shear_modulus"] * I_mean / l
                torsion = (sp.ImmutableMatrix(mt), sp.ImmutableMatrix([[gip, -gip], [-gip, gip]]))
            base = (sp.ImmutableMatrix(Mt), sp.ImmutableMatrix(Mr), sp.ImmutableMatrix(R))
            cached = _FORMS[key] = ((q, spin), mass, stiffness, gyro, torsion, base)
        return cached

    def _renames(self, ctx):
        """Per element: placeholder -> expression of the segment's parameter symbols."""
        p = ctx.p
        (q, spin), *_ = self._forms_template()
        base = {q["l"]: p["length"] / self.elements, q["density"]: p["density"],
                q["youngs_modulus"]: p["youngs_modulus"], q["shear_modulus"]: p["shear_modulus"]}
        for n in ("shear_coefficient", "axial_force"):
            if n in p:
                base[q[n]] = p[n]
        out = []
        for k in range(self.elements):
            (doa, dia), (dob, dib) = self._node_diameters(p, k), self._node_diameters(p, k + 1)
            rename = dict(base)
            rename.update({q["do_a"]: doa, q["do_b"]: dob})
            if not self._solid():
                rename.update({q["di_a"]: dia, q["di_b"]: dib})
            out.append(rename)
        return out, spin

    def contribute(self, ctx):
        (_, _), mass_t, stiffness_t, gyro_t, torsion_t, _ = self._forms_template()
        renames, spin = self._renames(ctx)
        forms = []
        nodes = self.nodes()
        for rename, (a, b) in zip(renames, zip(nodes, nodes[1:])):
            rename = {**rename, spin: ctx.speed(self.start)}
            cx = [ctx.coord(a, "x"), ctx.coord(a, "thy"), ctx.coord(b, "x"), ctx.coord(b, "thy")]
            cy = [ctx.coord(a, "y"), ctx.coord(a, "thx"), ctx.coord(b, "y"), ctx.coord(b, "thx")]
            forms.append(QuadraticForm(coordinates=tuple(c[0] for c in cx + cy),
                                       speeds=tuple(c[1] for c in cx + cy),
                                       mass=mass_t.xreplace(rename), stiffness=stiffness_t.xreplace(rename),
                                       gyroscopic=gyro_t.xreplace(rename) if gyro_t is not None else None))
            if torsion_t is not None:
                (qa, ua), (qb, ub) = ctx.coord(a, "alpha"), ctx.coord(b, "alpha")
                forms.append(QuadraticForm(coordinates=(qa, qb), speeds=(ua, ub), mass=torsion_t[0].xreplace(rename),
                                           stiffness=torsion_t[1].xreplace(rename)))
        frame = base_frame(ctx)
        if frame is None:
            return Terms(quadratic=tuple(forms))
        return Terms(quadratic=tuple(forms), loads=self._base_rotation_loads(ctx, frame))

    def _base_rotation_matrices(self, ctx):
        import sympy as sp

        *_, (Mt, Mr, R) = self._forms_template()
        renames, spin = self._renames(ctx)
        rho = ctx.p["density"]
        Id = rho if self.rotary_inertia else sp.S.Zero  # times int I(s) ... inside Mr and R
        Ip = 2 * rho if self.gyroscopic else sp.S.Zero
        return [(Mt.xreplace(r), Mr.xreplace(r), R.xreplace(r), Id, Ip) for r in renames]

    def rigid_body_mass(self, ctx):
        import sympy as sp

        (_, _), mass_t, *_ = self._forms_template()
        renames, _ = self._renames(ctx)
        out = {}
        nodes = self.nodes()
        for rename, (a, b) in zip(renames, zip(nodes, nodes[1:])):
            M = mass_t.xreplace(rename)
            rx = M * sp.Matrix([1, 0, 1, 0, 0, 0, 0, 0])  # uniform field in x on (x, thy) of both nodes
            ry = M * sp.Matrix([0, 0, 0, 0, 1, 0, 1, 0])
            cx = [(a, "x"), (a, "thy"), (b, "x"), (b, "thy")]
            cy = [(a, "y"), (a, "thx"), (b, "y"), (b, "thx")]
            for k, (st, axis) in enumerate(cx + cy):
                qsym = ctx.coord(st, axis)[0]
                old = out.get(qsym, (sp.S.Zero, sp.S.Zero))
                out[qsym] = (old[0] + rx[k], old[1] + ry[k])
        return out


def _shape_moment(k, i, j):
    """``int_0^1 s^k N_i N_j ds`` with ``N_0 = 1 - s``, ``N_1 = s`` (a Beta function, rational)."""
    import sympy as sp

    a = (i == 0) + (j == 0)  # powers of (1 - s)
    b = 2 - a  # powers of s
    return sp.Rational(math.factorial(k + b) * math.factorial(a), math.factorial(k + b + a + 1))
