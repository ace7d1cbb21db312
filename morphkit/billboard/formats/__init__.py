"""The billboard asset files: one versioned ``.npz`` per asset, checked on load.

* :mod:`.assetfile` -- a ring asset (:class:`~morphkit.billboard.asset.BillboardAsset`);
* :mod:`.domefile` -- a relightable dome asset (:class:`~morphkit.billboard.domeasset.DomeAsset`).
"""
