"""A frame's silhouette IoU over the union of its billboards' boxes, from what each box holds alone.

A frame measures ``billboard-iou`` over the pixels of the union of its drawn billboards' boxes
(:func:`~morphkit.billboard.compare.frame_errors`), where a box's background is often another
billboard's silhouette; a table's cell knows one billboard whole and alone. :func:`union_iou`
combines the boxes by their *coverage*: billboard ``k``'s box is covered by the representation's
silhouette over a fraction ``a_k`` of its pixels, by the truth's over ``b_k`` and by both over
``i_k``; spread evenly over the box and independent of the other boxes', a pixel under the boxes
``K`` is covered by the representation with probability ``1 - prod_K (1 - a_k)``, by the truth with
``1 - prod_K (1 - b_k)`` and by neither with ``prod_K (1 - a_k - b_k + i_k)``, and the frame's IoU is
the sum over the union's pixels of their intersection's probabilities over that of their union's.
One box alone gives its own ``i / (a + b - i)``; disjoint boxes, their IoUs weighted by the pixels
of their silhouettes' union.

Convention
----------
Boxes are ``(r0, r1, c0, c1)``: rows ``r0:r1`` and columns ``c0:c1`` of the frame, as
:class:`~morphkit.billboard.Placement`'s ``roi``. The frame is taken in cells of ``step`` x ``step``
pixels, a box covering the cells its pixels touch (at least one); a union with no silhouette in
either frame has an IoU of 1, as :func:`~morphkit.imaging.metrics.shadow_iou` measures it.

``scripts/plan_frame_model.py`` holds it against frames drawn and measured (``docs/results/planning.md``).
"""

from __future__ import annotations

import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..validate import as_finite_array, as_shape

__all__ = ["union_iou"]


def union_iou(rois: np.ndarray, fractions: np.ndarray, shape: tuple[int, int], step: int = 4) -> float:
    """The frame's IoU over the union of ``rois`` from each box's coverage fractions (module notes).

    Parameters
    ----------
    rois : (N, 4) int
        Each box's ``(r0, r1, c0, c1)`` inside the frame.
    fractions : (N, 3) float
        Each box's ``(a, b, i)``: the fractions of its pixels the representation, the truth and both
        cover (``0 <= i <= min(a, b)``, ``a + b - i <= 1``).
    shape : (H, W)
        The frame's size, pixels.
    step : int, optional
        Pixels per cell side.

    Returns
    -------
    float
        The IoU in ``[0, 1]`` (1 for an empty union or no boxes).

    Raises
    ------
    ValidationError
        Boxes or fractions of another shape, a frame size that is not one, a box outside the frame
        or empty, fractions that no silhouettes could cover (outside ``[0, 1]``, ``i`` above ``a``
        or ``b``, a union above 1).

    Examples
    --------
    One box: its own IoU. Two disjoint boxes of 16 and 48 pixels, each silhouette covering half its
    box, at IoU 1 and 0.5: theirs weighted by their unions' pixels (8 and 32), (8 + 16) / (8 + 32):

    >>> import numpy as np
    >>> from morphkit.plan.framecoverage import union_iou
    >>> round(union_iou(np.array([[0, 4, 0, 4]]), np.array([[0.5, 0.5, 0.25]]), (8, 16)), 6)
    0.333333
    >>> round(union_iou(np.array([[0, 4, 0, 4], [4, 8, 0, 12]]),
    ...                 np.array([[0.5, 0.5, 0.5], [0.5, 0.5, 1 / 3]]), (8, 16)), 6)
    0.6
    """
    h, w = as_shape(shape, "shape")
    boxes = np.asarray(rois)
    if boxes.ndim != 2 or boxes.shape[1] != 4 or not np.issubdtype(boxes.dtype, np.integer):
        raise ValidationError(expected_got("rois", "an (N, 4) integer array of (r0, r1, c0, c1)",
                                           f"{boxes.dtype} of shape {boxes.shape}"))
    f = as_finite_array(fractions, "fractions", shape=(len(boxes), 3))
    a, b, i = f.T
    eps = tol.COVERAGE_FRACTION_ATOL
    bad = (f < -eps).any(axis=1) | (i > np.minimum(a, b) + eps) | (a + b - i > 1 + eps)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise ValidationError(expected_got(f"fractions[{k}]", "0 <= i <= min(a, b) and a + b - i <= 1",
                                           f.tolist()[k]))
    r0, r1, c0, c1 = boxes.T
    out = (r0 < 0) | (c0 < 0) | (r1 > h) | (c1 > w) | (r1 <= r0) | (c1 <= c0)
    if out.any():
        k = int(np.flatnonzero(out)[0])
        raise ValidationError(expected_got(f"rois[{k}]", f"a non-empty box inside the frame {(h, w)}",
                                           boxes.tolist()[k]))
    if step < 1:
        raise ValidationError(expected_got("step", "an integer >= 1", step))
    logs = np.zeros((3, -(-h // step), -(-w // step)))
    covered = np.zeros(logs.shape[1:], bool)
    with np.errstate(divide="ignore"):
        lg = np.log(np.clip(1.0 - np.stack([a, b, a + b - i], axis=1), 0.0, 1.0))
    for k in range(len(boxes)):
        rows = slice(r0[k] // step, -(-r1[k] // step))
        cols = slice(c0[k] // step, -(-c1[k] // step))
        logs[:, rows, cols] += lg[k][:, None, None]
        covered[rows, cols] = True
    pa, pb, pu = (1.0 - np.exp(x[covered]) for x in logs)
    union = float(pu.sum())
    return 1.0 if union <= 0.0 else float(np.clip((pa + pb - pu).sum() / union, 0.0, 1.0))
