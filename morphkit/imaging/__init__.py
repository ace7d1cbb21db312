"""Images of a scene and their measures: compositing, shading, cut-outs and the exact truth.

Core, below both wings (they and everything above use it):

* :mod:`.composite` -- shadows into a rendered frame, premultiplied-alpha "over";
* :mod:`.shading` -- the one shading model of relit images (Lambert, ambient, suns, points);
* :mod:`.appearance` -- the colours of a mesh's render items;
* :mod:`.cutout` -- cut-out alpha at points on a mesh's surface, as the renderer samples it;
* :mod:`.groundtruth` -- exact shadow references by ray casting, independent of any shadow map;
* :mod:`.metrics` -- image and shadow error metrics, optionally under a mask;
* :mod:`.fidelity` -- scenes whose every pixel has a derivable value (the renderer's checks).
"""
