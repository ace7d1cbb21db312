from .cli import main

if __name__ == "__main__":  # guarded: `morphkit bake` starts worker processes that import this module
    raise SystemExit(main())
