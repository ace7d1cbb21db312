"""Bake time of a billboard asset: what is drawn once per asset, before any frame.

* :mod:`.ringviews` -- :func:`~.ringviews.bake_asset`: a mesh's reference views on a ring, every
  pair's morph prepared;
* :mod:`.bakelook` -- the render items, lights and content hash of what a bake draws.

Many assets on many workers: :mod:`morphkit.bake`.
"""
