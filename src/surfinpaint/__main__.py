"""``python -m surfinpaint``: the command line."""

from surfinpaint.app.cli import program

if __name__ == "__main__":
    raise SystemExit(program())
