"""Build functions of the sweep tests (a module, so worker processes import them by name or file).

A Jeffcott rotor with a rub stator: one disk on an elastic support
(wn = 100 rad/s, zeta = 0.15), spin ``speed``. Without contact its unbalance
response is the closed form ``unbalance_amplitude``.
"""

import math
import os
import signal
import time

import sympy as sp

import rotorkit as rk

SPIN = 300.0  # rad/s
MASS, STIFFNESS, DAMPING = 2.0, 2.0e4, 60.0  # wn = 100 rad/s, zeta = 0.15
CLEARANCE = 1e-4  # m


def build_jeffcott(rub_stiffness=2e4, eccentricity=1e-4, singular_load=0.0, speed=SPIN, friction=0.1, crash=0.0):
    """The rotor; ``singular_load`` adds a load that is NaN after t = 0.3 s; ``crash`` = 1 kills the worker once."""
    if crash == 1.0:
        _crash_once()
    _hold()
    elements = [
        rk.Rotor(name="R", stations=(1,), speed=speed),
        rk.Disk(station=1, mass=MASS, radius=0.1, eccentricity=eccentricity, torsion=False),
        rk.ElasticSupport(station=1, stiffness=STIFFNESS, damping=DAMPING),
        rk.RubStator(station=1, clearance=CLEARANCE, contact_stiffness=rub_stiffness, friction_coefficient=friction),
    ]
    if singular_load:
        elements.append(rk.Maneuver.profile(lambda t: singular_load * sp.log(0.3 - t), lambda t: 0 * t))
    return rk.Model(elements, name="jeffcott-rub")


build_jeffcott.OUTPUTS = {"t_end": 0.5, "bending": "x1"}
build_jeffcott.UNITS = {"rub_stiffness": "N/m", "eccentricity": "m", "speed": "rad/s", "friction": "",
                        "singular_load": "N", "crash": ""}


def _crash_once():
    """Kill this worker process (SIGKILL, as the OOM killer would) the first time, in a worker only."""
    marker = os.environ.get("RK_SWEEP_CRASH_MARKER")
    if not marker or str(os.getpid()) == os.environ.get("RK_SWEEP_DRIVER_PID"):
        return
    try:
        fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return
    os.write(fd, str(os.getpid()).encode())
    os.close(fd)
    os.kill(os.getpid(), signal.SIGKILL)


def _hold():
    """Sleep ``RK_SWEEP_HOLD`` seconds in a worker (not the driver): keeps workers busy for as long as a test needs."""
    hold = float(os.environ.get("RK_SWEEP_HOLD", "0"))
    if hold and str(os.getpid()) != os.environ.get("RK_SWEEP_DRIVER_PID"):
        time.sleep(hold)


def unbalance_amplitude(eccentricity=1e-4, speed=SPIN):
    r = speed / math.sqrt(STIFFNESS / MASS)
    zeta = DAMPING / (2.0 * math.sqrt(STIFFNESS * MASS))
    return eccentricity * r**2 / math.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2)
