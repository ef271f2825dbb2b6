"""The ``rotorkit`` command line: one module per command in this package.

To add a command, write ``rotorkit/cli/<command>.py`` with ``register(sub)``
(adds its subparser and ``set_defaults(func=main)``) and ``main(args)``
(returns the exit code), and list the module in :data:`COMMANDS`.
"""

import argparse
import importlib
import sys

from ..errors import RotorkitError
from .common import parse_assignment

__all__ = ["main", "build_parser", "parse_assignment", "COMMANDS"]

#: command modules, in the order ``rotorkit --help`` lists them
COMMANDS = ("run", "equations", "accuracy", "stiffness", "modes", "campbell", "unbalance", "static", "sweep",
            "validate", "export", "cache", "listing", "periodic", "audit")


def build_parser():
    parser = argparse.ArgumentParser(prog="rotorkit", description="Rotordynamics models: derive, compile, simulate.")
    sub = parser.add_subparsers(dest="command", required=True)
    for name in COMMANDS:
        importlib.import_module(f"{__name__}.{name}").register(sub)
    return parser


def main(argv=None):
    """Entry point of the ``rotorkit`` command: returns 0, or 2 on a usage or input error (130 on Ctrl-C)."""
    from ..interrupts import watching

    try:
        with watching():  # a Ctrl-C that other code swallowed is raised again at the next checkpoint
            return _main(argv)
    except KeyboardInterrupt:  # also while the commands are still being imported
        print("rotorkit: interrupted", file=sys.stderr)
        return 130


def _main(argv):
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exit_:  # argparse printed its usage message
        return int(exit_.code or 0)
    from ..plotting.basic import standalone_figures

    try:
        with standalone_figures():  # figures written to files: never on pyplot's current axes
            return args.func(args)
    except RotorkitError as err:
        print(f"rotorkit: error: {err}", file=sys.stderr)
        return 2
