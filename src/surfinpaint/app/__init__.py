"""The application: command line, per-hole report, figures and the paper's experiment set.

The only layer that prints or draws.
"""
