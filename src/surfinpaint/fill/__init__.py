"""Hole filling: the pipeline, holes and their selection, creases, the self-check, and the methods.

``liepa/`` is the conventional fill (triangulate, refine, fair: Liepa 2003); ``conformal/`` is
the λ-H method (Lui, Wen, Gu). Nothing here reads files or draws pictures.
"""
