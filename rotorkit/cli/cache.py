"""``rotorkit cache``: show or clear the cache of generated models."""


def register(sub):
    ca = sub.add_parser("cache", help="show or clear the cache of generated models")
    ca.add_argument("action", choices=("info", "clear"), help="info: folder, count and size; clear: remove all")
    ca.set_defaults(func=main)


def main(args):
    from ..codegen import cache

    if args.action == "clear":
        print(f"removed {cache.clear()} cached model(s) from {cache.cache_dir()}")
    else:
        folder, count, size = cache.info()
        print(f"{folder}: {count} cached model(s), {size / 1e6:.1f} MB")
    return 0
