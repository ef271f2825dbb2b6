"""Beam shaft elements from geometry: Euler-Bernoulli or Timoshenko, with gyroscopics.

The element matrices are *derived*, once per element kind, from the
kinetic and strain energy of a beam with shape functions
(:func:`plane_template`), then instantiated per element by substitution:
a 100-element rotor costs 100 substitutions, not 100 integrations.

Per bending plane the beam has a deflection ``w(z)`` and a cross-section
rotation ``beta(z)`` with the shear strain ``gamma = w' - beta``::

    V = 1/2 int EI beta'^2 + kappa G A gamma^2 dz
    T = 1/2 int rho A w'^2 + rho I beta'^2 dz   (dots: time derivatives)

The shape functions are the interdependent ones that solve the static,
unloaded Timoshenko equations exactly (``w`` cubic,
``beta = w' + c3 phi l^2 / 2``, ``phi = 12 EI / (kappa G A l^2)``); with
``phi = 0`` they are the Hermite cubics of the Euler-Bernoulli beam. In the
x-z plane ``(w, beta) = (x, thy)``; in the y-z plane
``(w, beta) = (y, -thx)`` (``thx = -dy/dz``). Spinning at ``Omega`` the
beam carries ``T_g = Omega int rho I_p thx' thy dz`` (``I_p = 2 I``), the
gyroscopic coupling of the two planes. Optional torsion: linear shape
functions for ``alpha``, ``T = 1/2 int rho I_p alpha'^2``,
``V = 1/2 int G I_p alpha_z^2``.
"""

import functools
import math
from dataclasses import dataclass

from ..errors import ParameterError, TopologyError
from .base import Element, loaded_types
from .material import Material
from .rotor import check_station

__all__ = ["BeamSegment", "plane_template", "shape_functions", "THEORIES"]

THEORIES = ("timoshenko", "euler-bernoulli")
_FORMS = {}  # structural variant -> element matrices in placeholder symbols (BeamSegment._forms_template)


@functools.cache
def shape_functions():
    """The interdependent Timoshenko shape functions of one bending plane (sympy).

    Returns
    -------
    tuple
        ``(z, l, phi, N_w, N_beta)``: the axial coordinate, the element
        length, ``phi = 12 EI / (kappa G A l^2)`` and the 1x4 rows with
        ``w(z) = N_w q``, ``beta(z) = N_beta q`` over ``q = (w1, beta1, w2, beta2)``.
    """
    import sympy as sp

    z, l = sp.symbols("z l", positive=True)
    phi = sp.Symbol("phi", nonnegative=True)
    c = sp.symbols("c0:4")
    w = c[0] + c[1] * z + c[2] * z**2 + c[3] * z**3
    beta = sp.diff(w, z) + c[3] * phi * l**2 / 2
    q = sp.symbols("w1 b1 w2 b2")
    solution = sp.solve([w.subs(z, 0) - q[0], beta.subs(z, 0) - q[1], w.subs(z, l) - q[2], beta.subs(z, l) - q[3]],
                        c, dict=True)[0]
    w_q, beta_q = sp.expand(w.subs(solution)), sp.expand(beta.subs(solution))
    Nw = sp.Matrix([[sp.diff(w_q, qi) for qi in q]])
    Nb = sp.Matrix([[sp.diff(beta_q, qi) for qi in q]])
    return z, l, phi, Nw, Nb


@functools.cache
def plane_template():
    """Element matrices of one bending plane, derived from the energies with shape functions.

    Returns
    -------
    dict
        ``"symbols"``: (l, phi); and 4x4 matrices over ``(w1, beta1, w2, beta2)``:
        ``"stiffness"`` (times EI), ``"translational_mass"`` (times rho A),
        ``"rotary_mass"`` (times rho I; also ``int N_beta^T N_beta dz``, the
        gyroscopic integral per ``rho I_p``); ``"geometric"``, the geometric
        stiffness per unit axial force ``int N_w'^T N_w' dz``;
        ``"torque"``, ``int N_w'^T N_w'' dz`` (the torque's geometric
        stiffness per unit torque couples the planes through it); and
        ``"rotary_vector"``, 4x1, ``int N_beta^T dz``. Entries are rational in
        l and phi.
    """
    import sympy as sp

    z, l, phi, Nw, Nb = shape_functions()
    gamma = sp.simplify(sp.diff(Nw, z) - Nb)  # constant shear strain per unit dof, proportional to phi
    dNb = sp.diff(Nb, z)

    def integral(A):
        return A.applyfunc(lambda e: sp.factor(sp.integrate(sp.expand(e), (z, 0, l))))

    # kappa G A = 12 EI / (phi l^2): the shear energy is finite (-> 0) as phi -> 0
    shear = (gamma.T * gamma).applyfunc(lambda e: sp.factor(sp.cancel(e * 12 / (phi * l**2))))
    stiffness = (integral(dNb.T * dNb) + shear * l).applyfunc(sp.factor)
    return {
        "symbols": (l, phi),
        "stiffness": stiffness,
        "translational_mass": integral(Nw.T * Nw),
        "rotary_mass": integral(Nb.T * Nb),
        "rotary_vector": integral(Nb.T),
        "geometric": integral(sp.diff(Nw, z).T * sp.diff(Nw, z)),
        "torque": integral(sp.diff(Nw, z).T * sp.diff(Nw, z, 2)),
    }


def _cross(v):
    """The matrix of ``v x`` (3x3)."""
    import sympy as sp

    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def cowper_shear_coefficient(poisson_ratio, diameter_ratio):
    """Cowper's (1966) shear coefficient of a hollow circular section.

    ``kappa = 6 (1 + nu) (1 + m^2)^2 / ((7 + 6 nu) (1 + m^2)^2 + (20 + 12 nu) m^2)``
    with ``m = d_i / d_o`` (solid: ``6 (1 + nu) / (7 + 6 nu)``, 0.886 for nu = 0.3).
    Works on floats and sympy expressions.
    """
    m2 = diameter_ratio**2
    nu = poisson_ratio
    return 6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)


#: most finite elements one BeamSegment is split into
MAX_ELEMENTS = 2000


@dataclass(frozen=True, slots=True, kw_only=True)
class BeamSegment(Element):
    """A shaft segment of tubular cross-section as ``elements`` beam finite elements.

    Each node (the two end stations and ``elements - 1`` internal nodes,
    named ``<label>_1``, ``<label>_2``, ... from ``start``) gets the lateral
    coordinates ``x``, ``y`` and the tilts ``thx``, ``thy``; with
    ``torsion=True`` also ``alpha``. Every element has the consistent mass
    matrix (translation and, by default, rotary inertia), the bending
    stiffness (with shear deformation for ``theory="timoshenko"``) and the
    gyroscopic matrix at its rotor's speed. See the module docstring and
    ``docs/elements.md`` for the derivation and the sign convention.

    Parameters
    ----------
    start, end : int or str
        Stations at the two ends (on one rotor).
    length : float or pint.Quantity
        Segment length (m), > 0.
    outer_diameter : float or pint.Quantity
        d_o (m), > 0.
    inner_diameter : float or pint.Quantity
        d_i (m), 0 <= d_i < d_o.
    material : Material, optional
        Fills ``density``, ``youngs_modulus``, ``shear_modulus`` not given.
    density, youngs_modulus, shear_modulus : float or pint.Quantity, optional
        rho (kg/m^3), E (Pa), G (Pa).
    theory : {"timoshenko", "euler-bernoulli"}
    shear_coefficient : float, optional
        kappa; default Cowper's value for the hollow circle
        (:func:`cowper_shear_coefficient`, with nu = E / (2 G) - 1).
    rotary_inertia : bool
        Include the sections' rotary inertia rho I (default True).
    gyroscopic : bool
        Include the gyroscopic coupling at the rotor speed (default True).
    torsion : bool
        Add torsional coordinates and distributed torsional inertia and stiffness.
    elements : int
        Number of equal finite elements (>= 1).
    axial_force : float or pint.Quantity, optional
        Axial force P in the segment (N), tension positive, compression
        negative: the geometric stiffness ``P int w'^2 dz / 2`` per bending
        plane (a compressive load softens the shaft and buckles it at
        ``P = -pi^2 E I / L^2`` pinned-pinned). None (default) adds no term.
    torque : float or pint.Quantity, optional
        Constant axial torque T in the segment (N m; its sign gives the
        handedness of the buckled helix only): the geometric stiffness of
        Greenhill's axial torque, which couples the two bending planes and
        buckles a pinned-pinned shaft at ``|T| = 2 pi E I / L``. The
        coupling is not symmetric (an axial torque is not conservative): its
        symmetric part enters the stiffness matrix, its skew part acts as a
        circulatory load. See ``docs/elements.md``. None (default) adds no
        term.

    Examples
    --------
    >>> b = BeamSegment(start=1, end=2, length=0.25, outer_diameter=0.05, material=Material.steel())
    >>> round(b.mass_value(), 3)
    3.834
    """

    start: int | str = None
    end: int | str = None
    length: float = None
    outer_diameter: float = None
    inner_diameter: float = 0.0
    axial_force: float | None = None
    torque: float | None = None
    density: float | None = None
    youngs_modulus: float | None = None
    shear_modulus: float | None = None
    shear_coefficient: float | None = None
    material: Material | None = None
    theory: str = "timoshenko"
    rotary_inertia: bool = True
    gyroscopic: bool = True
    torsion: bool = False
    elements: int = 1

    _units = {
        "length": ("m", "positive"),
        "outer_diameter": ("m", "positive"),
        "inner_diameter": ("m", "nonnegative"),
        "density": ("kg/m**3", "positive"),
        "youngs_modulus": ("Pa", "positive"),
        "shear_modulus": ("Pa", "positive"),
        "shear_coefficient": ("", "positive"),
        "axial_force": ("N", None),
        "torque": ("N*m", None),
    }
    _latex_names = {"length": "L", "outer_diameter": "d_o", "inner_diameter": "d_i", "density": r"\rho",
                    "youngs_modulus": "E", "shear_modulus": "G", "shear_coefficient": r"\kappa", "axial_force": "P",
                    "torque": "T"}
    structure_matrices = ("mass", "stiffness")

    def __post_init__(self):
        if self.material is not None:
            if not isinstance(self.material, Material):
                raise ParameterError(f"BeamSegment {self.start!r}-{self.end!r}: material = {self.material!r}: "
                                     "expected a rotorkit Material, e.g. Material.steel()")
            for f in ("density", "youngs_modulus", "shear_modulus"):
                if getattr(self, f) is None:
                    object.__setattr__(self, f, getattr(self.material, f))
        Element.__post_init__(self)

    def _validate(self):
        who = f"BeamSegment {self.start!r}-{self.end!r}"
        object.__setattr__(self, "start", check_station(who, self.start, "start"))
        object.__setattr__(self, "end", check_station(who, self.end, "end"))
        if self.start == self.end:
            raise ParameterError(f"{who}: start and end are the same station; give two stations")
        for f, unit in (("length", "m"), ("outer_diameter", "m"), ("density", "kg/m^3"),
                        ("youngs_modulus", "Pa"), ("shear_modulus", "Pa")):
            if getattr(self, f) is None:
                hint = " or material=Material.steel() (or another Material)" if f in (
                    "density", "youngs_modulus", "shear_modulus") else ""
                raise ParameterError(f"{who}: {f} is required ({unit}){hint}")
        if not self.inner_diameter < self.outer_diameter:
            raise ParameterError(
                f"{who}: inner_diameter = {self.inner_diameter:g} m must be smaller than outer_diameter = "
                f"{self.outer_diameter:g} m"
            )
        nu = self.youngs_modulus / (2 * self.shear_modulus) - 1
        if not -1 < nu < 0.5:
            raise ParameterError(
                f"{who}: shear_modulus = {self.shear_modulus:g} Pa with youngs_modulus = {self.youngs_modulus:g} Pa "
                f"gives a Poisson ratio {nu:.4g} outside (-1, 0.5); expected shear_modulus > E/3"
            )
        if self.theory not in THEORIES:
            raise ParameterError(f"{who}: theory = {self.theory!r}: expected one of {THEORIES}")
        for f in ("rotary_inertia", "gyroscopic", "torsion"):
            if not isinstance(getattr(self, f), bool):
                raise ParameterError(f"{who}: {f} = {getattr(self, f)!r}: expected True or False")
        if isinstance(self.elements, bool) or not isinstance(self.elements, int) or self.elements < 1:
            raise ParameterError(f"{who}: elements = {self.elements!r}: expected an int >= 1")
        if self.elements > MAX_ELEMENTS:  # checked before any node, symbol or matrix exists
            states = 2 * 5 * self.elements  # x, y, two tilts and a twist per node, and their rates
            raise ParameterError(
                f"{who}: elements = {self.elements}: about {states // 2} coordinates; a segment holds at most "
                f"{MAX_ELEMENTS} elements (the dense state matrices of the linear analyses alone would take "
                f"{8 * states**2 / 1e9:.3g} GB, and the derivation time grows with the count): use fewer elements")
        if self.shear_coefficient is not None and self.theory != "timoshenko":
            raise ParameterError(f"{who}: shear_coefficient is only used with theory='timoshenko'")

    def structure(self):
        base = Element.structure(self)
        # an absent axial force or torque leaves the structure (and the cache keys) of a plain beam unchanged
        return base[:2] + (tuple(v for v in base[2] if v[0] != "material" and v not in (
            ("axial_force", True), ("torque", True))),)

    # -- topology -------------------------------------------------------------
    def _default_label(self):
        return f"beam{self.start}_{self.end}"

    def nodes(self):
        """Stations of the element nodes from ``start`` to ``end`` (internal ones named ``<label>_k``)."""
        inner = tuple(f"{self.label()}_{k}" for k in range(1, self.elements))
        return (self.start,) + inner + (self.end,)

    def attached_stations(self):
        return (self.start, self.end)

    def internal_stations(self):
        return tuple((s, self.start) for s in self.nodes()[1:-1])

    def _axes(self):
        return ("x", "y", "thx", "thy") + (("alpha",) if self.torsion else ())

    def coordinates(self):
        return tuple((s, a) for s in self.nodes() for a in self._axes())

    def inertia(self):
        return self.coordinates()

    def stiffness_links(self):
        nodes = self.nodes()
        links = []
        for a, b in zip(nodes, nodes[1:]):
            links.append(tuple((s, axis) for s in (a, b) for axis in ("x", "thy")))
            links.append(tuple((s, axis) for s in (a, b) for axis in ("y", "thx")))
            if self.torsion:
                links.append(((a, "alpha"), (b, "alpha")))
        return tuple(links)

    def check(self, model):
        turning_base = loaded_types("base_motion.BaseRotation")  # (its module is loaded if the model has one)
        for e in model.elements if turning_base else ():
            if isinstance(e, turning_base):
                z0, z1 = e.axial_position(self.start), e.axial_position(self.end)
                if z0 is not None and z1 is not None and not math.isclose(z1 - z0, self.length, rel_tol=1e-9,
                                                                          abs_tol=1e-12):
                    raise TopologyError(
                        f"BeamSegment {self.label()!r}: BaseRotation.axial_positions put {self.start!r} at {z0:g} m "
                        f"and {self.end!r} at {z1:g} m, {z1 - z0:g} m apart, but the segment is {self.length:g} m "
                        "long; expected end = start + length (z increases from start to end)")
        ra, rb = model.rotor_of(self.start), model.rotor_of(self.end)
        if ra is not rb:
            raise TopologyError(
                f"BeamSegment {self.label()!r}: stations {self.start!r} (rotor {ra.name!r}) and {self.end!r} "
                f"(rotor {rb.name!r}) are on different rotors; couple rotors with a bearing"
            )

    def explain(self, model, problem, coordinates):
        if problem == "support" and any(a == "alpha" for _, a in coordinates):
            return (f"BeamSegment {self.label()!r}: torsion=True gives its nodes torsional coordinates with no "
                    "torsional stiffness path to the drive; add a ShaftSegment with torsional_stiffness from one "
                    "node to a station without torsional coordinate, or drop torsion")
        return None

    def effects(self):
        return frozenset({"gyroscopic"}) if self.gyroscopic else frozenset()

    # -- values ---------------------------------------------------------------
    def mass_value(self):
        """Mass of the segment (kg)."""
        return self.density * math.pi * (self.outer_diameter**2 - self.inner_diameter**2) / 4 * self.length

    def _section(self, p):
        """(rho A, rho I, EI, kappa G A, G Ip, l) of one element, from the parameter symbols ``p``."""
        import sympy as sp

        do, di = p["outer_diameter"], p["inner_diameter"]
        if self.inner_diameter == 0:  # structural: a solid shaft has no d_i terms
            area, inertia = sp.pi * do**2 / 4, sp.pi * do**4 / 64
        else:
            area, inertia = sp.pi * (do**2 - di**2) / 4, sp.pi * (do**4 - di**4) / 64
        rho, E, G = p["density"], p["youngs_modulus"], p["shear_modulus"]
        if self.shear_coefficient is not None:
            kappa = p["shear_coefficient"]
        else:
            kappa = cowper_shear_coefficient(E / (2 * G) - 1, di / do if self.inner_diameter != 0 else 0)
        return rho * area, rho * inertia, E * inertia, kappa * G * area, G * 2 * inertia, p["length"] / self.elements

    def element_matrices(self, p):
        """Per-plane 4x4 (K, M) over ``(w1, beta1, w2, beta2)`` and the gyroscopic integral, from symbols ``p``."""
        import sympy as sp

        tpl = plane_template()
        l_sym, phi_sym = tpl["symbols"]
        rhoA, rhoI, EI, kGA, _, l = self._section(p)
        phi = 12 * EI / (kGA * l**2) if self.theory == "timoshenko" else sp.S.Zero
        subs = {l_sym: l, phi_sym: phi}
        K = (EI * tpl["stiffness"]).xreplace(subs)
        if self.axial_force is not None:  # geometric stiffness P int N_w'^T N_w' dz
            K = K + p["axial_force"] * tpl["geometric"].xreplace(subs)
        Mr = tpl["rotary_mass"].xreplace(subs)
        M = rhoA * tpl["translational_mass"].xreplace(subs)
        if self.rotary_inertia:
            M = M + rhoI * Mr
        return K, M, Mr

    def _forms_template(self):
        """(placeholders, mass, stiffness, gyroscopic) 8x8 of one element, in placeholder symbols.

        Built once per structural variant (theory, flags, solid or hollow,
        elements) and renamed to each element's parameter symbols with
        ``xreplace``: the matrix products and substitutions of the template
        are not redone for every element of a long rotor.
        """
        import sympy as sp

        key = (self.theory, self.rotary_inertia, self.gyroscopic, self.inner_diameter == 0,
               self.shear_coefficient is None, self.elements, self.axial_force is not None, self.torque is not None)
        cached = _FORMS.get(key)
        if cached is None:
            names = ("outer_diameter", "inner_diameter", "density", "youngs_modulus", "shear_modulus",
                     "shear_coefficient", "length", "axial_force", "torque")
            p = {n: sp.Symbol(f"_beam_{n}", real=True) for n in names}
            spin = sp.Symbol("_beam_spin", real=True)
            K, M, Mr = self.element_matrices(p)
            rhoI = self._section(p)[1]
            sign = sp.diag(1, -1, 1, -1)  # y-z plane: (w, beta) = (y, -thx)
            Ky, My = sign * K * sign, sign * M * sign
            Z = sp.zeros(4, 4)
            mass = sp.ImmutableMatrix(sp.BlockMatrix([[M, Z], [Z, My]]))
            stiffness = sp.ImmutableMatrix(sp.BlockMatrix([[K, Z], [Z, Ky]]))
            circulatory = None
            if self.torque is not None:
                # Greenhill's axial torque: virtual work int (EI w'' - i T w') dw''* over w = u + i v, i.e.
                # rows of u against v: T int N''^T N' = T A^T, rows of v against u: -T A^T (A = int N_w'^T N_w'');
                # v = N_w (sign q_y). Symmetric part -> stiffness, skew part -> circulatory load.
                l_sym, phi_sym = plane_template()["symbols"]
                rhoA, rhoI, EI, kGA, _, l = self._section(p)
                phi = 12 * EI / (kGA * l**2) if self.theory == "timoshenko" else sp.S.Zero
                B = p["torque"] * plane_template()["torque"].xreplace({l_sym: l, phi_sym: phi}).T
                KT = sp.zeros(8, 8)
                KT[:4, 4:] = B * sign
                KT[4:, :4] = -sign * B
                symmetric = ((KT + KT.T) / 2).applyfunc(sp.factor)
                stiffness = sp.ImmutableMatrix(stiffness + symmetric)
                circulatory = sp.ImmutableMatrix(((KT - KT.T) / 2).applyfunc(sp.factor))
            gyro = None
            if self.gyroscopic:
                # T_g = Omega rho I_p int thx' thy dz, beta_y = N_beta (sign q_y) so thx = -N_beta (sign q_y),
                # thy = N_beta q_x -> -u_y^T (Omega rho I_p sign Mr) q_x: rows of the y-plane, columns of x
                gyro = sp.zeros(8, 8)
                gyro[4:, :4] = -spin * 2 * rhoI * (sign * Mr)
                gyro = sp.ImmutableMatrix(gyro)
            cached = _FORMS[key] = ((p, spin), mass, stiffness, gyro, circulatory)
        return cached

    def contribute(self, ctx):
        import sympy as sp

        from .base_motion import base_frame
        from .terms import QuadraticForm, Terms

        p = ctx.p
        (placeholders, spin_symbol), mass_t, stiffness_t, gyro_t, circ_t = self._forms_template()
        rename = {v: p[k] for k, v in placeholders.items() if k in p}
        rename[spin_symbol] = ctx.speed(self.start)
        mass, stiffness = mass_t.xreplace(rename), stiffness_t.xreplace(rename)
        gyro = gyro_t.xreplace(rename) if gyro_t is not None else None
        circulatory = circ_t.xreplace(rename) if circ_t is not None else None
        forms, loads = [], {}
        nodes = self.nodes()
        for a, b in zip(nodes, nodes[1:]):
            cx = [ctx.coord(a, "x"), ctx.coord(a, "thy"), ctx.coord(b, "x"), ctx.coord(b, "thy")]
            cy = [ctx.coord(a, "y"), ctx.coord(a, "thx"), ctx.coord(b, "y"), ctx.coord(b, "thx")]
            coords = tuple(c[0] for c in cx + cy)
            speeds = tuple(c[1] for c in cx + cy)
            forms.append(QuadraticForm(coordinates=coords, speeds=speeds, mass=mass, stiffness=stiffness,
                                       gyroscopic=gyro))
            if circulatory is not None:  # the skew part of the torque's stiffness: the load -K_skew q
                for q, f in zip(coords, -(circulatory * sp.Matrix(coords))):
                    if f != 0:
                        loads[q] = loads.get(q, sp.S.Zero) + f
            if self.torsion:
                _, rhoI, _, _, GIp, l = self._section(p)
                (qa, ua), (qb, ub) = ctx.coord(a, "alpha"), ctx.coord(b, "alpha")
                Jl = 2 * rhoI * l
                forms.append(QuadraticForm(coordinates=(qa, qb), speeds=(ua, ub),
                                           mass=sp.Matrix([[Jl / 3, Jl / 6], [Jl / 6, Jl / 3]]),
                                           stiffness=sp.Matrix([[GIp / l, -GIp / l], [-GIp / l, GIp / l]])))
        frame = base_frame(ctx)
        if frame is not None:
            for q, f in self._base_rotation_loads(ctx, frame).items():
                loads[q] = loads.get(q, sp.S.Zero) + f
        return Terms(quadratic=tuple(forms), loads=loads) if loads else Terms(quadratic=tuple(forms))

    # -- a turning base (BaseRotation) -----------------------------------------
    def node_positions(self, positions):
        """Axial positions (m) of the nodes, from ``positions`` (station -> z) of the start or end station (else 0)."""
        if self.start in positions:
            z0 = positions[self.start]
        elif self.end in positions:
            z0 = positions[self.end] - self.length
        else:
            z0 = 0.0
        return tuple(z0 + k * self.length / self.elements for k in range(self.elements + 1))

    def _base_rotation_loads(self, ctx, frame):
        """Loads of the turning base on the distributed mass and the spinning sections.

        Translation: the loads ``-int rho A N_w^T (W' x r + W x (W x r) + 2 W x r')`` with
        ``r = (x(z), y(z), z) - c``; every field in it (``x``, ``y``, ``z``, 1) is exactly
        interpolated by the shape functions, so the integral is the translational mass matrix
        times nodal vectors. Rotation: :func:`tilt_kinetic` per unit length (``rho I``,
        ``rho I_p``) integrated over the element with the rotation shape functions
        (:func:`~rotorkit.elements.base_motion.tilt_loads`).
        """
        import sympy as sp

        from .base_motion import tilt_loads

        per_element = self._base_rotation_matrices(ctx)
        W, c = frame.W, frame.c
        A = _cross(frame.Wd) + _cross(W) * _cross(W)
        B = 2 * _cross(W)
        Ac = A * c
        S = sp.diag(1, -1, 1, -1)
        spin = ctx.speed(self.start)
        # on (x_a, thy_a, x_b, thy_b, y_a, thx_a, y_b, thx_b): thy = beta_x, thx = -beta_y = -S (y-plane)
        Z4 = sp.zeros(4, 4)
        Vb, Va = sp.Matrix(sp.BlockMatrix([[sp.eye(4), Z4]])), sp.Matrix(sp.BlockMatrix([[Z4, -S]]))
        nodes, z = self.nodes(), self.node_positions(frame.positions)
        loads = {}
        for k, (na, nb) in enumerate(zip(nodes, nodes[1:])):
            Mt, Mr, R, Id, Ip = per_element[k]
            cx = [ctx.coord(na, "x"), ctx.coord(na, "thy"), ctx.coord(nb, "x"), ctx.coord(nb, "thy")]
            cy = [ctx.coord(na, "y"), ctx.coord(na, "thx"), ctx.coord(nb, "y"), ctx.coord(nb, "thx")]
            X, UX = sp.Matrix([q for q, _ in cx]), sp.Matrix([u for _, u in cx])
            Y, UY = S * sp.Matrix([q for q, _ in cy]), S * sp.Matrix([u for _, u in cy])  # (w, beta) of the y-z plane
            Z, ONE = sp.Matrix([z[k], 1, z[k + 1], 1]), sp.Matrix([1, 0, 1, 0])
            ax = A[0, 0] * X + A[0, 1] * Y + A[0, 2] * Z - Ac[0] * ONE + B[0, 0] * UX + B[0, 1] * UY
            ay = A[1, 0] * X + A[1, 1] * Y + A[1, 2] * Z - Ac[1] * ONE + B[1, 0] * UX + B[1, 1] * UY
            Q = sp.Matrix.vstack(-Mt * ax, -S * (Mt * ay))
            if Id != 0 or Ip != 0:
                q8 = sp.Matrix([q for q, _ in cx + cy])
                u8 = sp.Matrix([u for _, u in cx + cy])
                Q += tilt_loads(Id, Ip, spin, W, ctx.t, q8, u8, Va, Vb, Mr, R)
            for (q, _), f in zip(cx + cy, Q):
                if f != 0:
                    loads[q] = loads.get(q, sp.S.Zero) + f
        return loads

    def _base_rotation_matrices(self, ctx):
        """Per element: (M_t, M_r, R, I_d, I_p) of one plane for :meth:`_base_rotation_loads`.

        ``M_t`` the translational mass matrix; ``M_r = int N_beta^T N_beta dz``
        and ``R = int N_beta^T dz`` weighted so that ``I_d M_r``, ``I_p M_r``
        (``I_d R``...) are the section inertias' integrals (``I_d = rho I``,
        ``I_p = 2 rho I`` per unit length here; 0 when the flag is off).
        """
        import sympy as sp

        tpl = plane_template()
        l_sym, phi_sym = tpl["symbols"]
        rhoA, rhoI, EI, kGA, _, l = self._section(ctx.p)
        phi = 12 * EI / (kGA * l**2) if self.theory == "timoshenko" else sp.S.Zero
        subs = {l_sym: l, phi_sym: phi}
        Mt = rhoA * tpl["translational_mass"].xreplace(subs)
        Mr = tpl["rotary_mass"].xreplace(subs)
        R = tpl["rotary_vector"].xreplace(subs)
        Id = rhoI if self.rotary_inertia else sp.S.Zero
        Ip = 2 * rhoI if self.gyroscopic else sp.S.Zero
        return [(Mt, Mr, R, Id, Ip)] * self.elements

    def rigid_body_mass(self, ctx):
        import sympy as sp

        p = ctx.p
        _, M, _ = self.element_matrices(p)
        sign = sp.diag(1, -1, 1, -1)
        rx = M * sp.Matrix([1, 0, 1, 0])  # consistent load of a uniform field on (w1, beta1, w2, beta2)
        ry = sign * rx
        out = {}
        nodes = self.nodes()
        for a, b in zip(nodes, nodes[1:]):
            for k, (s, axis) in enumerate(((a, "x"), (a, "thy"), (b, "x"), (b, "thy"))):
                q = ctx.coord(s, axis)[0]
                old = out.get(q, (sp.S.Zero, sp.S.Zero))
                out[q] = (old[0] + rx[k], old[1])
            for k, (s, axis) in enumerate(((a, "y"), (a, "thx"), (b, "y"), (b, "thx"))):
                q = ctx.coord(s, axis)[0]
                old = out.get(q, (sp.S.Zero, sp.S.Zero))
                out[q] = (old[0], old[1] + ry[k])
        return out
