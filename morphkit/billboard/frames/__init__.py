"""A scene of billboards, frame by frame: instances, the per-frame plan and the compositor.

* :mod:`.instances` -- which asset stands where, turned how far, how large;
* :mod:`.field` -- :class:`~.field.BillboardScene`: assets, instances and a backdrop;
* :mod:`.frametypes` -- the value types of one frame (placements, plan, stats);
* :mod:`.planner` -- the stages of a frame's plan: cull, face, level of detail, clip, order;
* :mod:`.frustum`, :mod:`.facing`, :mod:`.lod` -- culling and clipping, how a quad turns, which
  pyramid level;
* :mod:`.cache` -- the bounded LRU morph cache;
* :mod:`.compositor` -- billboard images onto a frame, back to front (depth where they interpenetrate);
* :mod:`.backdrop` -- ground, sky and fog;
* :mod:`.paths` -- camera paths: the paper's pan, an orbit, a fly-over.
"""
