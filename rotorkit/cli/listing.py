"""``rotorkit list``: the bundled presets."""


def register(sub):
    ls = sub.add_parser("list", help="list the bundled presets")
    ls.set_defaults(func=main)


def main(args):
    from ..presets import list_presets, preset_module

    for name in list_presets():
        print(f"{name}: {preset_module(name).DESCRIPTION}")
    return 0
