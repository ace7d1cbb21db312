"""Planning a scene to an error budget: what each representation's error is, measured against the
asset's own mesh, what a frame's error will be, and the cheapest choice that meets the budget.

* :mod:`.budget` -- an error budget (``KEY=VALUE``: billboard PSNR and IoU, shadow IoU, the
  fraction of frames, a frame time), checked, and the frames that meet it counted;
* :mod:`.errortable` -- per asset and representation, the error of its billboards against its
  mesh over on-screen size and elevation (measured once per asset, saved as a versioned file);
* :mod:`.predict` -- a frame's mean per-billboard error predicted from those tables;
* :mod:`.representations` -- what a plan chooses among (culling, classic card, nearest view, view
  morph, real mesh), per band of on-screen size and elevation, and the modes that draw each band;
* :mod:`.planner` -- every frame's billboards predicted in every representation, and the choice;
* :mod:`.shadowchoice` -- the frame's shadow (sun-atlas texels, the sun's softness) chosen to a
  ``shadow-iou`` budget from its candidates as measured;
* :mod:`.planfile` -- the plan as a file (``plan.json``), read back by ``morphkit render --plan``;
* :mod:`.lodchain` -- the plan's bands as an engine's levels of detail (``morphkit export --plan``).

The command that measures, plans and verifies a scene is :mod:`morphkit.programs.planning.planrun`.
"""

from .budget import Budget
from .errortable import ErrorTable, measure_error_table
from .planfile import ScenePlan, read_plan
from .planner import choose, predict_frames
from .predict import instance_views, predict_frame_error
from .representations import REPRESENTATIONS, BandChoice

__all__ = ["Budget", "ErrorTable", "measure_error_table", "instance_views", "predict_frame_error",
           "REPRESENTATIONS", "BandChoice", "predict_frames", "choose", "ScenePlan", "read_plan"]
