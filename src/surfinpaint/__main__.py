"""``python -m surfinpaint``: the command line."""

from surfinpaint.app.program import program

if __name__ == "__main__":
    raise SystemExit(program())
