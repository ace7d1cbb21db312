"""Bake time of a shadow atlas: the control points the run-time warps move.

* :mod:`.controls` -- automatic control points: silhouette boxes, anchor depths, lifting to 3-D;
* :mod:`.fold` -- fold-over relaxation of the destination control points.
"""
