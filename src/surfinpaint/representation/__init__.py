"""The λ-H representation (the paper's grid world): λ and H fields on conformal grids, their
estimation, inpainting and the rebuild of a surface from them, and ``represent``/``rebuild``
for whole disk-like meshes. Knows nothing of holes or pictures."""
