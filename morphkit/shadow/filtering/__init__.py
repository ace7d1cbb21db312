"""Filtered lookups and smooth penumbrae: an extension of the warped maps to soft shadows.

* :mod:`.filtered` -- the fraction of a light cell one depth map says a point sees;
* :mod:`.depthtables` -- its per-map tables (summed-area tables, a max-depth pyramid);
* :mod:`.penumbra` -- smooth penumbrae from few light samples (PCF and PCSS over the samples).
"""
