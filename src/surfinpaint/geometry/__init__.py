"""Mesh toolkit: primitives and operators, distances, cutting, validation, repair, conformal maps.

The lowest layer: it knows nothing of holes, files or pictures.
"""
