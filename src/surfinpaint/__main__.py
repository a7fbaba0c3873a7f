"""``python -m surfinpaint``: the command line."""

from surfinpaint.app.cli import main

if __name__ == "__main__":
    raise SystemExit(main())
