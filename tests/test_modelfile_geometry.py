"""Model files keep what was written: geometry, one material, tables with units."""

from __future__ import annotations

import tomllib

import pytest

import rotorkit as rk
from rotorkit.elements import BeamSegment, Disk, DiskGeometry, Material, SpeedProfile
from rotorkit.errors import ParameterError
from rotorkit.modelfile import dumps_model, loads_model


def rotor():
    steel = Material.steel()
    return rk.Model([
        rk.Rotor(name="R", stations=(1, 2), speed=SpeedProfile.table([0.0, 1.0], [0.0, 300.0])),
        BeamSegment(start=1, end=2, length=0.5, outer_diameter=0.05, material=steel),
        Disk.from_geometry(station=2, width=0.07, inner_diameter=0.05, outer_diameter=0.28, material=steel),
        rk.elements.LinearBearing(station=1, kxx=1e6, kyy=1e6),
        rk.elements.LinearBearing(station=2, kxx=1e6, kyy=1e6),
    ], name="geometry")


def test_the_file_holds_the_geometry_one_material_and_units():
    model = rotor()
    data = tomllib.loads(dumps_model(model))
    rot, beam, disk = data["element"][:3]
    assert set(disk) == {"type", "station", "eccentricity", "phase", "torsion", "geometry"}  # no mass, inertias
    assert disk["geometry"]["width"] == "0.07 m" and disk["geometry"]["outer_diameter"] == "0.28 m"
    assert disk["geometry"]["inner_diameter"] == "0.05 m" and disk["geometry"]["material"]["name"] == "steel"
    assert not {"density", "youngs_modulus", "shear_modulus"} & set(beam)  # only in its material
    assert beam["material"] == {"type": "Material", "density": "7810.0 kg/m**3", "youngs_modulus": "211000000000.0 Pa",
                                "shear_modulus": "81200000000.0 Pa", "name": "steel"}  # as given, no Poisson ratio
    assert rot["speed"]["times"] == ["0.0 s", "1.0 s"] and rot["speed"]["speeds"] == ["0.0 rad/s", "300.0 rad/s"]


def test_round_trip_is_exact_and_the_disk_is_the_same():
    model = rotor()
    loaded, _ = loads_model(dumps_model(model))
    assert loaded.elements == model.elements and loaded.parameters == model.parameters
    disk = loaded.elements[2]
    assert disk.geometry == model.elements[2].geometry
    steel = Material.steel()
    m = steel.density * 3.141592653589793 * (0.14**2 - 0.025**2) * 0.07  # rho pi (ro^2 - ri^2) w
    assert disk.mass == pytest.approx(m, rel=1e-14)
    assert disk.polar_inertia == pytest.approx(m * (0.14**2 + 0.025**2) / 2, rel=1e-14)


def test_changing_a_mass_parameter_drops_the_geometry():
    changed = rotor().with_values(disk2_mass=40.0).elements[2]
    assert changed.mass == 40.0 and changed.geometry is None
    assert changed.radius == pytest.approx(0.14)


@pytest.mark.parametrize("kwargs, match", [
    (dict(mass=1.0), "mass = 1.0 disagrees with its geometry"),
    (dict(geometry="steel disk"), "expected a DiskGeometry"),
])
def test_a_disk_and_its_geometry_must_agree(kwargs, match):
    geometry = DiskGeometry(width=0.07, outer_diameter=0.28, material=Material.steel())
    with pytest.raises(ParameterError, match=match):
        Disk(station=1, **{"geometry": geometry, **kwargs})
