"""Files: what morphkit reads and writes, and the folders its commands write into.

* :mod:`.fileio` -- atomic writes, checked archives, refusing non-regular files;
* :mod:`.outfolder` -- a command's output folder: what it holds, when it may be replaced.

The formats themselves live with what they store (an atlas file beside its atlas).
"""
