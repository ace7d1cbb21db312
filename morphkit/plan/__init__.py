"""Planning a scene to an error budget: what each representation's error is, measured against the
asset's own mesh at bake time, and what a frame's error will be.

* :mod:`.errortable` -- per asset and representation, the error of its billboards against its
  mesh over on-screen size and elevation (measured once, stored beside the bake, reused);
* :mod:`.predict` -- a frame's error predicted from those tables, for a camera and the instances.
"""

from .errortable import ErrorTable, measure_error_table
from .predict import instance_views, predict_frame_error

__all__ = ["ErrorTable", "measure_error_table", "instance_views", "predict_frame_error"]
