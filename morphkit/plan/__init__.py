"""Planning a scene to an error budget: what each representation's error is, measured against the
asset's own mesh, and what a frame's error will be.

* :mod:`.budget` -- an error budget (``KEY=VALUE``: billboard PSNR and IoU, shadow IoU, the
  fraction of frames, a frame time), checked, and the frames that meet it counted;
* :mod:`.errortable` -- per asset and representation, the error of its billboards against its
  mesh over on-screen size and elevation (measured once per asset, saved as a versioned file);
* :mod:`.predict` -- a frame's error predicted from those tables, for a camera and the instances.

The planner that chooses each asset's representation from them is not built yet.
"""

from .budget import Budget
from .errortable import ErrorTable, measure_error_table
from .predict import instance_views, predict_frame_error

__all__ = ["Budget", "ErrorTable", "measure_error_table", "instance_views", "predict_frame_error"]
