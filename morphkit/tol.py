"""Numerical tolerances, in one place (as trimesh does).

Every threshold morphkit uses to decide that something is degenerate, equal or
valid lives here, with the reason for its value. Tests import these rather than
repeating numbers.
"""

from __future__ import annotations

#: Smallest absolute signed area (pixels^2) of a warp triangle that still counts as a
#: triangle. A 1e-6 px^2 triangle maps its whole source onto a point.
TRIANGLE_AREA_PX2 = 1e-6

#: Relative tolerance used when asking "is this matrix orthonormal / this
#: vector unit length" on poses given by users (float32 poses round to ~1e-7).
POSE_ORTHO = 1e-5

#: Smallest extent (scene units) of a light, camera frustum or bounding box.
MIN_EXTENT = 1e-9

#: Depth-buffer values pyrender reports as "no surface" (it writes 0.0).
PYRENDER_BACKGROUND = 0.0

#: Minimum relative distance (fraction of object size) of a camera from an
#: object's bounding box before the camera is considered inside the object.
CAMERA_CLEARANCE = 1e-3

#: Ray origins for ray-cast shadows are pushed this far (scene units) towards the
#: light, so a point lying on the occluder's surface does not hit itself. Embree
#: intersects in float32: ~1e-7 relative, i.e. 1e-7 units on a unit-size
#: object; 1e-4 is 1000x that and 1/10000 of the object size (sample meshes
#: are normalised to size 1), far below a shadow-map texel.
RAY_OFFSET = 1e-4

#: A shadow ray that hits a cut-out hole (a masked texel of a leaf card) is cast
#: again from :data:`RAY_OFFSET` past the hit, at most this many times in all
#: (:func:`morphkit.imaging.groundtruth.hard_visibility`). A ray through a plant crosses
#: one card per layer of leaves (a few to a few tens); a ray grazing a card can
#: land on the same card again after a step of ``RAY_OFFSET`` (float32 hits), so
#: the bound stops that walk. A ray still in holes after it counts as shadowed,
#: with a :class:`~morphkit.imaging.groundtruth.CutoutLayersWarning`.
CUTOUT_MAX_LAYERS = 64

#: Outward margin (pixels) by which a warp's destination mesh boundary is pushed
#: when deciding which output pixel centres it covers, so that centres lying on
#: the boundary (the last row/column of an identity warp over the whole image)
#: are covered, as a closed mesh should. Rounding in user coordinates is ~1e-12 px,
#: far below it; samples at such centres move by < 1e-6 px (invisible).
MESH_BOUNDARY_PX = 1e-6

#: Largest vertex coordinate (scene units, absolute) of a mesh morphkit reads. trimesh's vertex
#: merging hashes coordinates scaled by 1e8 into int64 (about 9.2e18), so it overflows past
#: ~9e10; 1e9 is 90x below that and a million kilometres on a metre scale: no real model.
MESH_MAX_COORD = 1e9

#: Most nodes of a glTF file morphkit reads (:mod:`morphkit.meshes.gltf`, checked on its JSON before
#: trimesh reads it): trimesh poses and merges every node in Python, so the read's time grows with
#: the count (docs/RESULTS.md); one asset of ten thousand parts is already a scene, not an object.
MAX_GLTF_NODES = 10_000

#: Relative length below which a mesh counts as flat in a direction
#: (:func:`morphkit.meshes.check_mesh`): its vertices' second principal extent
#: (or second bounding-box extent) over its first. Vertex coordinates round at
#: ~1e-16 of the mesh size; 1e-9 is far above that and far below any real
#: feature (a nanometre on a one-metre object).
MESH_ZERO_LENGTH_REL = 1e-9

#: A mesh face whose area is below this times the squared largest extent of the
#: mesh has zero area (:func:`morphkit.meshes.check_mesh`); a mesh whose faces
#: all have zero area has no surface to draw and is refused. The cross product
#: of collinear float64 edges of length ~L rounds to ~1e-16 L^2; 1e-12 L^2 is
#: 10^4 times that and a face of 1e-6 x 1e-6 of the object.
MESH_ZERO_AREA_REL = 1e-12

#: Slack (in UV units, i.e. texture widths) when counting how often a part's texture
#: repeats to cover its UVs (:func:`morphkit.meshes.parts.merge_parts`): UVs within
#: 1e-6 of an integer count as on it, so a UV of ``1.0000000001`` or ``-1e-9`` (float
#: noise of exporters) does not add a whole repeat; 1e-6 of a texture is a 1/250
#: texel at 4096 texels, which changes no sampled texel.
UV_TILE_SLACK = 1e-6

#: Central-difference step (metres, before normalisation) of the implicit sample
#: shapes' field gradient, for the Newton projection of a polygonised mesh onto
#: the surface (:func:`morphkit.meshes.implicit.project`): 1e-4 of shapes ~2 m
#: tall, far below their smallest feature (~3 cm) and far above the float64
#: rounding of the field (~1e-16), so the difference quotient is the gradient.
SDF_GRADIENT_STEP = 1e-4

#: Floor of the squared field gradient in that projection: a point where the
#: field is flat (its gradient vanishes, only at a shape's medial axis, far from
#: the surface) is not thrown away by a division by ~0. The smooth signed fields
#: have gradients of norm ~1 near their surface, 1e-12 never changes a real step.
SDF_GRADIENT_FLOOR = 1e-12

# --- generic zeros and equalities (one name each, instead of bare epsilons) ---

#: A float64 magnitude at or below this is zero: the floor of a norm, determinant or
#: weight that a value is divided by. Normal float64 values go down to ~2.2e-308, so
#: 1e-300 only catches exact (or underflowed) zeros and never changes a real quotient.
ZERO = 1e-300

#: Two float64 quantities of the same scale are equal when they differ by less than
#: this times that scale (coordinates, depths, parameters on a grid). float64 rounds
#: at ~1e-16 relative, and a few dozen operations stay below ~1e-14; 1e-9 is far above
#: that and far below any difference a user could mean (a nanometre in a metre).
REL_EQUAL = 1e-9

#: Two pixel coordinates (or control points, in pixels) are the same point when they
#: differ by at most this many pixels: a shift of 1e-6 px moves no sample visibly,
#: while float32 image coordinates up to 8192 px round at ~5e-4 px only in float32
#: storage, which morphkit does not compare (control points are float64).
PX_EQUAL = 1e-6

#: Floor of a float32 alpha or accumulated weight that colour is divided by (to leave
#: premultiplied form, or to normalise a weighted sum): float32 resolves ~6e-8 near 1,
#: and an alpha of 1e-6 is 1/3900 of one 8-bit step, i.e. invisible: below it a pixel
#: is transparent and its colour is 0.
ALPHA_FLOOR = 1e-6

#: A visibility within this of 0 or 1 is umbra or lit, not penumbra, in the soft-shadow
#: bench's banding measure (:func:`morphkit.bench.soft_suite.banding`): a filtered lookup that
#: sums lit and shadowed terms leaves round-off of about 1e-16 in the umbra, which a strict
#: ``0 < v < 1`` counted as penumbra (the measure then moved with the summation order, not
#: with the image: 0.0063 vs 0.0100 on the teapot for the same visibility to 2e-13). The sun
#: disc's filtered lookup (:mod:`morphkit.sunlit.sundisc`) returns such values as 0 or 1.
PENUMBRA_EPS = 1e-6

#: Two unit vectors are parallel when ``abs(dot) > 1 - PARALLEL_DOT`` (about 0.08 degrees):
#: a look-at up vector, a light along an axis. Near that the cross product's direction
#: is ill-conditioned (its length is ~sqrt(2e-6) = 1.4e-3).
PARALLEL_DOT = 1e-6

# --- light cameras fitted to points (morphkit.scene.light_view) --------------

#: Nearest a fitted orthographic light camera's near plane may be (scene units): the
#: plane sits a margin in front of the nearest point, and this keeps it positive
#: (CameraModel refuses znear <= 0) when the points reach the camera. A thousandth
#: of a sample mesh's size (they are normalised to size 1), far below any feature.
LIGHT_FIT_MIN_ZNEAR = 1e-3

#: Depth (scene units) added on both sides of the points' depth range when fitting a
#: perspective light camera, so that points all at one depth (a flat, light-facing
#: set) still get ``zfar > znear * (1 + REL_EQUAL)``; a millionth of a sample mesh
#: changes no depth a 24-bit buffer can store.
LIGHT_FIT_DEPTH_PAD = 1e-6


# --- size limits (checked before anything is allocated) ---------------------

#: Bytes of memory per pixel that an offscreen GL context and its first draw take (checked
#: before the context is created: :mod:`morphkit.render`, where Mesa would die of a failed
#: allocation instead of reporting it). Measured on llvmpipe (OSMesa): 12 B/px at context
#: creation and a 35 B/px peak after the first colour-and-depth draw (address space, at
#: 2048^2, 4096^2 and 8192^2); 48 leaves a third on top for other drivers and draws.
GL_BYTES_PER_PIXEL = 48

#: Bytes of memory per pixel a context's first one-pass frame draw adds (checked before each:
#: :meth:`morphkit.render.Renderer.frame_pass` and ``gbuffer_pass``, which share it; its framebuffer
#: object of two colour attachments and depth, on OSMesa beside OSMesa's own buffer). Measured on
#: llvmpipe: a 27-30 B/px rise of the peak address space at 2048^2 and 4096^2 (none at later draws);
#: 40 leaves a third on top.
GL_FRAME_PASS_BYTES_PER_PIXEL = 40

#: Most pixels an image, depth map or render may have (8192 x 8192 = 2**26). A
#: frame holds several per-pixel buffers at once (unprojected world points and
#: normals, float64/float32 (H, W, 3); lit and unlit colour; depth; visibility):
#: about 60 bytes a pixel, i.e. ~4 GB at this size. Larger sizes were refused
#: only by a raw ``MemoryError`` after seconds of work (20000^2) or not at all;
#: they are now a ``ValidationError`` from :func:`morphkit.validate.as_shape`
#: before any allocation. The benchmarks go up to 1024^2, 64x below.
MAX_IMAGE_PIXELS = 2**26

#: Most bytes one array morphkit allocates for the caller's sizes may take
#: (4 GiB): a shadow atlas's maps (``ky * kx * H * W`` float32) are the largest;
#: a 3 x 3 atlas of 8192^2 maps (2.25 GiB) fits, a 9 x 9 one (20 GiB) does not.
MAX_BUFFER_BYTES = 2**32

#: Most texels one texture may have (4096 x 4096). The renderer keeps every texture
#: as RGBA uint8 with its mipmaps in the GL context (4/3 x 64 MiB = 85 MiB at this
#: size, in main memory under OSMesa) besides the numpy copy it converts from; a
#: billboard bake keeps one context per image shape. Real-time assets rarely exceed
#: 4096^2 per material; a larger one is refused (downscale it) rather than failing
#: deep inside GL or exhausting memory.
MAX_TEXTURE_PIXELS = 4096 * 4096

#: Most texels on one side of a texture. OpenGL 3.3 only promises 1024
#: (``GL_MAX_TEXTURE_SIZE``); llvmpipe (OSMesa) and desktop GPUs of the last decade
#: allow 16384; 8192 stays below every one of those, and a 8192 x 2048 strip still fits
#: :data:`MAX_TEXTURE_PIXELS`.
MAX_TEXTURE_SIDE = 8192

#: Largest side (pixels) of a video morphkit writes (``shadows.webm``, ``billboards.webm``, and
#: ``.mp4`` files a caller names: ``mp4v`` stores width and height in 13 bits, and FFmpeg refuses
#: 8192 there), checked before any frame is rendered so that a size no writer takes fails at once.
MAX_VIDEO_SIDE = 8190

#: Most frames one command renders along a path (``shadows``, ``billboards``,
#: ``viewmorph --frames``): 100000 frames is an hour of video at 25 fps; each frame is
#: a file, and the frame list (cameras, positions) is built before the first frame,
#: so a count without a cap allocated without bound (10^9 frames) before any error.
MAX_FRAMES = 100_000

#: Most billboard instances one scene places (``morphkit billboards --n``). Instances
#: are drawn one by one each frame and placed up front (positions, sizes, rotations);
#: the paper's forest scenes have a few thousand, so 100000 leaves room while 10^11
#: would allocate terabytes before any error.
MAX_INSTANCES = 100_000

#: Most reference views of one billboard asset (as :class:`morphkit.bake.BillboardKind`
#: allows): each view is a rendered image kept in the asset (and a morph pair with its
#: neighbour); beyond 64 the neighbouring views are under 6 degrees apart and a morph
#: between them no longer differs visibly from either.
MAX_BILLBOARD_VIEWS = 64

#: Largest reference view side of a billboard asset, pixels (as
#: :class:`morphkit.bake.BillboardKind` allows): 64 views of 2048^2 RGBA with their
#: mip levels are already ~1.4 GB.
MAX_BILLBOARD_SIDE = 2048

#: Most local worker processes of a bake (``morphkit bake --workers``): each is a
#: Python process with its own GL context (~200 MB); 256 is beyond any single
#: machine's useful count, while an uncapped count started processes until memory ran out.
MAX_LOCAL_WORKERS = 256

#: Most threads of a banded pass (``MORPHKIT_WARP_THREADS``): each takes a band of rows
#: and a stack of its own; beyond one a core, they only wait on each other.
MAX_WARP_THREADS = 256

#: Largest EGL device index (``MORPHKIT_EGL_DEVICE``): far beyond the GPUs of any one machine,
#: so that a typo (a port number, a PCI address) is refused rather than tried.
MAX_EGL_DEVICE = 1023

#: Most instances of one ``bench scene`` field (``morphkit bench scene --instances``): its
#: ``sun-change`` section poses every instance's copy of an asset of up to 50k faces into one mesh
#: that is drawn and ray-cast, about 5e7 faces (gigabytes) at the suite's largest default of 1000,
#: so twice that is the most a machine of tens of GB holds (10^9 grew past 23 GB until killed).
MAX_BENCH_INSTANCES = 2000

#: Most assets of the ``bench bake`` library (``morphkit bench bake --assets``): each is a mesh file
#: written to a temporary folder and baked once per phase, so a count without a cap wrote files
#: until the disk was full; 16x the 256 assets the suite's projection targets.
MAX_BENCH_ASSETS = 4096

#: Largest seed a command takes (``billboards --seed``): numpy's generators take any
#: non-negative integer; one that fits 64 bits is what a user can write down and repeat.
MAX_SEED = 2**64 - 1

#: Most light samples of an area light (``n_u * n_v``, or rows of an explicit
#: sample array). A soft shadow's visibility is a multiple of ``1 / N``: at
#: 4096 (64 x 64) that step is already 16x finer than one 8-bit grey level, and
#: every sample costs one shadow map per frame (a warp or a render), so more
#: samples only cost time (10^4 x 10^4 samples took gigabytes before failing).
MAX_LIGHT_SAMPLES = 4096

#: Filtered (penumbra) shadow lookups (:mod:`morphkit.shadow.filtered`): a kernel whose
#: half-widths are both below this many texels is the hard lookup (nearest texel), and a
#: wider one is at least this wide on each axis. Half a texel is where a box stops
#: being narrower than the texel it stands on: below it, filtering only blurs the
#: map's own texel edges; the hard lookup then gives a light of zero extent its hard
#: shadow exactly.
PENUMBRA_MIN_HALF_TEXEL = 0.5

#: Largest ``|x|`` or ``|y|`` (pixels) of a mesh warp's control points
#: (:mod:`morphkit.warp`); beyond it a ValidationError. Ten million pixels is
#: 1000x the side of a 10^4-pixel image, so any mesh reaching off an image
#: fits; there float64 still resolves an edge crossing to ~2e-9 px and float32
#: maps to 1 px, while at 1e20 px the crossings of an image's pixel centres
#: cancel to nothing and the warp silently covered no pixel.
MAX_COORD_PX = 1e7

# --- view morphing (morphkit.viewmorph) -------------------------------------

#: Default inlier threshold (pixels) of the robust fundamental-matrix fit
#: (Sampson distance) and of the homography-degeneracy test (transfer
#: distance). SIFT keypoints are localised to ~0.3-0.5 px; 1 px keeps good
#: matches and rejects gross outliers. Exact projected points are ~1e-9 px.
VM_THRESHOLD_PX = 1.0

#: Points whose centred scatter has singular values s2 / s1 below this ratio are
#: collinear: a 1000:1 elongated cloud leaves F (and any homography) undetermined
#: in the short direction at the noise levels above.
VM_COLLINEAR_RATIO = 1e-3

#: Two pairs closer than this (pixels, in either image) are duplicates; the later
#: one is dropped. Closer points only make sliver triangles in the morph mesh.
VM_DUPLICATE_PX = 1e-3

#: The pairs are "explained by a homography" (planar scene, pure rotation, zero
#: baseline, identical images) when the homography's inliers reach this fraction
#: of the fundamental matrix's inliers at the same threshold: every pair that
#: fits F (almost) also fits the homography, so the data do not determine F
#: (F = [e1]x H for any e1). 5% leaves room for the few off-plane points that
#: a robust F fit would otherwise be built on.
VM_HOMOGRAPHY_INLIER_RATIO = 0.95

#: An epipole whose homogeneous w is below this fraction of the norm of (x, y) is at
#: infinity (a 1e-9 relative w puts it ~1e9 image widths away).
VM_EPIPOLE_INFINITY = 1e-9

#: The views are already parallel (rectified; the pre-warp is skipped) when the
#: inlier pairs' RMS vertical disparity y1 - y0 is at most this (pixels): below
#: half a pixel a rectification would move points by less than its resampling blur.
VM_PARALLEL_Y_PX = 0.5

#: A component of a unit-norm vector or matrix of the view-morph geometry (an
#: epipole's in-plane direction, an epipolar line's direction, a normalised
#: pre-warp's Jacobian row) below this is zero: SVD null vectors of float64
#: matrices are accurate to ~1e-15, so 1e-12 only catches true degeneracies
#: (an epipole exactly on the optical axis, the line at infinity).
VM_UNIT_ZERO = 1e-12

#: Seitz & Dyer's rotated (unit-norm) F must reach the form [[0,0,0],[0,0,a],[0,b,c]];
#: its other entries may be at most this. The rotations are built from the
#: epipoles in float64 (~1e-15); 1e-6 leaves room for F's conditioning (its
#: second singular value over the first down to ~1e-9) and still refuses any F
#: that the construction did not rectify.
VM_ROTATED_F_RESIDUAL = 1e-6

#: Probability that the homography-degeneracy test's RANSAC misses a homography
#: that explains the pairs (:func:`morphkit.viewmorph.fundamental.homography_degeneracy`
#: sizes its sample count from it): one wrong "not degenerate" in a billion pairs.
VM_HOMOGRAPHY_MISS_PROB = 1e-9

#: Rectification is refused when an epipole lies inside the image grown by this
#: fraction of its diagonal on every side: the cameras (nearly) see each other
#: and no homography sends the epipole to infinity without tearing the image.
VM_EPIPOLE_MARGIN = 0.1

#: Largest anisotropy (ratio of the singular values of the local Jacobian) a
#: pre-warp may have anywhere over the image; 4:1 is a 76-degree tilt of the
#: image plane (cos = 1/4), beyond which the rectified image is mostly smear.
VM_MAX_ANISOTROPY = 4.0

#: Largest ratio between the local area scales of a pre-warp over its image
#: (and between the two images): beyond 16 (4x linear) one part of the image
#: is under-sampled 4x while another is blown up.
VM_MAX_SCALE_RATIO = 16.0

#: Largest rectified canvas side, as a multiple of the larger input side: a
#: bigger canvas means the pre-warp sends part of the image towards infinity.
VM_MAX_CANVAS_FACTOR = 4.0

#: Relative depth tolerance of the visibility test of geometric
#: correspondences: a point is visible if its depth is at most (1 + rtol) times
#: the rendered depth around its projection. 1% of a 3-unit camera distance is
#: 0.03 units: above the 24-bit depth quantisation (~1e-4 relative) and the
#: depth change across one pixel on moderately slanted surfaces, below the gap
#: between a surface and what it hides on the sample meshes (>= 0.05 units).
VM_VISIBILITY_RTOL = 0.01

#: Smallest absolute signed area (pixels^2) a morph-mesh triangle may reach for any
#: s in [0, 1]; smaller ones count as fold-overs and a vertex is dropped.
#: 1000x the warp's own refusal limit (tol.TRIANGLE_AREA_PX2) so float32 maps
#: never meet it.
VM_MIN_TRIANGLE_AREA_PX2 = 1e-3

#: Depth layers of a layered morph (``ViewMorpher(layers=k)``) overlap by this
#: fraction of the pairs' depth range, so that a surface cut by a layer edge is
#: drawn by both layers near the cut (the two meshes approximate the cut
#: differently; without overlap thin cracks open there). More overlap also
#: drags a little of the far side into the near layer; 0.02 keeps most of both
#: (docs/results/view_morphing.md: the layers' overlap swept).
VM_LAYER_OVERLAP = 0.02

#: The 1-D k-means of the depth layers stops when no centre moved by more than
#: this times the largest depth magnitude (at least 1): float64 means of depths
#: round at ~1e-16 relative, so 1e-12 is converged, and the layer cuts it gives
#: are far finer than any pixel's depth difference.
VM_KMEANS_CONVERGED_REL = 1e-12

#: Fewest distinctive (SIFT) matches two images must share for ``morphkit viewmorph`` to
#: take them for views of one scene when it finds the correspondences itself: the 8
#: pairs F needs (:func:`morphkit.viewmorph.plan_view_morph`'s minimum). Dense flow finds
#: forward-backward consistent pairs between any two images (17 to 1339 on four unrelated
#: synthetic pairs, which a robust F or a homography then explained: a double exposure),
#: so only the distinctive matches can tell; SIFT found 0, 3, 5 and 11 on those pairs.
#: Fewer than F's own minimum refuses what cannot be one scene's views; more does not prove
#: that the views are of one scene.
VM_MIN_SCENE_MATCHES = 8

#: Smallest side (pixels) of the images DIS optical flow runs on (``FlowMatcher`` pads
#: smaller ones with zeros): OpenCV's DIS refuses a side under 12, and (OpenCV 5.1,
#: measured) kills the process with a segfault on images under 16 rows high and 40 or
#: more wide (preset medium), or under 32 rows and 80 or more wide (fast, ultrafast);
#: from 32 rows and columns on, none did (up to 8000 wide, every preset).
VM_FLOW_MIN_SIDE = 32

#: Fewest pairs a depth layer may hold; with fewer, the layer count drops (the
#: fallback is reported in ``ViewMorpher.report.layers``). 8 is the pair count F needs,
#: and a layer's mesh needs its own pairs to move differently from its neighbours.
VM_MIN_LAYER_PAIRS = 8

#: A post-warp to a target camera is the least-squares homography over at most
#: this many pairs, spread over image 0: a fraction of the time of all the dense pairs for
#: a residual within a percent (docs/results/view_morphing.md: the post-warp's pairs).
VM_POST_FIT_PAIRS = 256

#: ``ViewMorpher(layers="auto")`` layers the morph when the single mesh had to
#: drop more than this fraction of its pairs to fold-overs. A heuristic, set
#: from the bench scenes (dense ``from_depth`` pairs, 256^2): the drop fraction
#: was 0.2% (teapot 10 deg) and 0.4% (cow 10 deg), where two layers cost
#: 0.001-0.003 IoU and up to 1.8 dB at a 10-degree baseline; 1.1-1.4% for the
#: chair at 10-20 deg and 3-23% for all three meshes at 20-60 deg, where two
#: layers changed IoU by -0.012 to +0.17 (mean over s: -0.002 to +0.11): a
#: small loss on the smooth meshes, a large gain where parts cross (chair).
#: Any value between 0.4% and 1.1% splits the bench cases alike.
VM_AUTO_LAYER_DROP = 0.005

#: How many layers ``layers="auto"`` uses when it layers: two took the chair at
#: 20 deg from 0.885 to 0.965 IoU (s = 1/2); three gave 0.963 at 1.4x the time.
VM_AUTO_LAYERS = 2

# --- billboard assets (morphkit.billboard) ----------------------------------

#: Fewest correspondences (from the two depth maps, before cleaning) a pair of
#: neighbouring reference views must share to be baked into an asset; fewer is
#: refused at bake time. 4x the 8 pairs F needs, so the robust fit has a margin;
#: a morph mesh with fewer points cannot follow an object's outline (the
#: bake's sampling gives ~500-1000 pairs for the sample meshes at 256^2 and
#: 45-60 degrees, and ~150-300 at 64^2).
BB_MIN_CORRESPONDENCES = 32

#: Depth tolerance of the bake's visibility test (a sample of one reference is seen by
#: the other when its depth there is within this of the other's depth map), in
#: bounding radii of the mesh: ``from_depth(rtol=BB_VISIBILITY_RADII / distance_factor)``.
#: A tolerance relative to the depth alone (:data:`VM_VISIBILITY_RTOL`) grows with the
#: bake distance: at 12 radii it took points 0.12 radii behind a surface for visible
#: (a chair's far legs), their pairs folded over, and a pair could not be morphed.
#: 0.04 is what 1% of the depth was at the former 4 radii.
BB_VISIBILITY_RADII = 0.04

#: Splat grid of a morph's coverage from depth (:func:`morphkit.billboard.splat_coverage`),
#: per image pixel and axis: 2 gives anti-aliased edges (4 levels of coverage per
#: pixel) at a quarter of the cost of 4.
BB_COVERAGE_SUPERSAMPLE = 2

#: Closing (fine-grid pixels) of the coverage splats: a reference pixel lands
#: about one image pixel (two fine pixels) from its neighbour in an in-between
#: view 30 degrees away, more on surfaces the reference sees at a grazing angle;
#: 5 closed every gap on the five sample meshes at 256^2 while 3 left holes
#: (IoU 0.74 against 0.98 on the cow, ``morphkit bench billboards``).
BB_COVERAGE_CLOSE_PX = 5

#: A morph pixel with alpha at or below this carries no usable colour (its
#: un-premultiplied colour is noise): the coverage from depth is not applied there.
BB_COVERAGE_MIN_ALPHA = 0.02

#: An asset file's stored reference cameras (``K`` in pixels, ``cam2world`` in scene
#: units) must match the camera rule's, recomputed from the file's quad and ring, to
#: within this (absolute): they were written from the same float64 numbers as JSON
#: (exact round trip), so any larger difference means an edited or foreign file.
BB_FILE_CAMERA_ATOL = 1e-9

#: A viewing direction's octahedral grid coordinate within this of an integer is on
#: that grid line (:meth:`~morphkit.billboard.impostor.OctahedralImpostor.weights`): the
#: direction of a frame, rebuilt from its azimuth and elevation, lands ~1e-15 off its
#: grid point, and must be served by that frame alone (weight exactly 1), not by it
#: and two others at weights of 1e-15.
IMP_GRID_SNAP = 1e-9

#: Floor of the cosine between a viewing direction and a frame's direction when the
#: viewing ray is intersected with the frame's plane (an octahedral impostor's
#: runtime). The frames of positive weight around a direction are within about one
#: grid cell of it (cosine >= 0.51 for 5 frames a side, >= 0.91 for 12); only on a
#: 3 x 3 grid does the top frame reach 90 degrees from a view at the horizon, where its
#: weight goes to 0: the floor keeps that frame from dividing by zero.
IMP_MIN_COS = 1e-3

# --- billboard scenes (morphkit.billboard) ---------------------------------

#: A camera is "directly above" a billboard (its facing about the up axis and its
#: viewing azimuth are undefined) when the horizontal distance to it is below this
#: fraction of the full distance: the direction then lies within 1e-6 rad (0.00006
#: deg) of vertical, where a float64 atan2 still works but the quad would spin
#: arbitrarily for a tiny camera move. The fallback is documented in
#: :mod:`morphkit.billboard.scene.facing`.
BB_ABOVE_RATIO = 1e-6

#: How far (degrees) above a ring asset's reference elevation (:class:`~morphkit.billboard.ring.ViewRing`)
#: its views still serve an eye (:meth:`ViewRing.band_deg`): its axial quads stand vertical, so
#: seen from higher the object's top, which no reference view holds, is missing and its
#: silhouette is the side view foreshortened by ``sin e``. Twenty degrees holds the pan, orbit and
#: fly paths (their eyes look down by 5 to 17 degrees); the fly-over (rising to 85) and the
#: top-down pan (90) leave it, and ``morphkit billboards`` takes dome views for them.
BB_RING_BAND_DEG = 20.0

#: A billboard quad whose screen projection covers less than this area (pixels^2)
#: is skipped as too small, whatever its height: an axial quad seen (nearly)
#: edge-on, e.g. from directly above, projects to a sliver whose homography is
#: (nearly) singular; half a pixel of area holds at most one pixel centre.
BB_MIN_AREA_PX2 = 0.5

#: A backdrop ray hits the ground plane ``z = 0`` only when its unit direction points
#: down by more than this (``dz < -BB_GROUND_RAY_DZ``); rays closer to horizontal
#: (the horizon row at most) show the sky, so the hit distance ``-z / dz`` stays finite.
BB_GROUND_RAY_DZ = 1e-12

#: A billboard pixel goes under the frame's depth buffer (:mod:`morphkit.billboard.scene.compositor`)
#: only when behind it by more than this fraction, so that surfaces that meet keep the plain
#: back-to-front "over" instead of flipping with the last bits of their depths.
BB_DEPTH_REL = 1e-5
#: A billboard pixel writes the depth buffer from this alpha on: the coverage measures'
#: silhouette threshold, so that a faint anti-aliased rim hides nothing behind it.
BB_DEPTH_OPAQUE_ALPHA = 0.5
#: Draws of a new position for an instance whose footprint meets another's
#: (:func:`morphkit.billboard.scene.instances.separate`) before it is counted as crowded: a free
#: place is found in a few draws until the field is nearly full.
BB_SCATTER_TRIES = 100

#: Largest forward-backward disagreement (pixels) of a pair from dense optical
#: flow (:class:`~morphkit.viewmorph.matching.FlowMatcher`): a pixel moved by the
#: forward flow and back by the backward flow must land within this of where it
#: started. Where DIS flow is right it is sub-pixel (median error 0.1 px on a
#: translated smooth texture, tests/test_viewmorph_images.py); at occlusions and
#: silhouettes the two flows disagree by pixels. 1 px is the inlier threshold of
#: F (:data:`VM_THRESHOLD_PX`): a kept pair is not already an outlier.
VM_FLOW_FB_PX = 1.0

#: An estimated F whose pre-warps are refused (epipole in or near an image, or
#: too distorting) is replaced by the affine F (epipoles at infinity) when the
#: affine F keeps at least this fraction of the general F's inliers: the views
#: are then nearly affine, and the general F's epipole is fitted to the
#: matches' noise. Set from exact pairs (``from_depth``), not from the success
#: rate: on the bench circle at 192^2 an affine F keeps, within 1 px, 97-100%
#: of the pairs at a 10-degree baseline, 79-100% at 20 and 64-100% at 40; 0.6
#: accepts views as far from affine as those and refuses pairs an affine F
#: explains worse (they fall back as any refused pair does).
VM_AFFINE_INLIER_RATIO = 0.6

#: ... and when, over the pairs both explain, the affine F's RMS Sampson
#: distance is at most this many times the general F's: the general F's extra
#: freedom then fits noise, not perspective. Exact pairs (``from_depth``,
#: ``from_geometry``) fit the general F to ~1e-9 px and an affine F to 0.1-0.5 px
#: (ratios above 1e5: a real epipole in the image stays refused); SIFT and flow
#: matches of the 72 bench pairs at 192^2 gave ratios 0.5-2.0 (1.1 median): a
#: factor of 2 means F must halve the residual to count as determined.
VM_AFFINE_RMS_RATIO = 2.0

# --- shadow wing (#23: named instead of bare literals; values unchanged) ------
#: A point projects through a light camera's texture matrix only when its
#: homogeneous ``w`` exceeds this (:func:`morphkit.shadow.lookup.shadow_visibility`):
#: ``w`` is the point's depth in front of a point light (scene units; 1 for a
#: directional light), so 1e-12 only refuses points on or behind the light's
#: plane, where ``x / w`` would blow up.
SHADOW_LOOKUP_W_MIN = 1e-12

#: Floor of the cosine between a receiver's normal and the light direction in the
#: slope bias's ``tan = sin / cos`` (:class:`~morphkit.shadow.lookup.ShadowBias`):
#: it only keeps a grazing surface (cos = 0) from dividing by zero; the tangent is
#: clamped at ``ShadowBias.max_tan`` (far below 1e6) anyway.
SHADOW_GRAZING_COS = 1e-6

#: Two rendered depths of one pixel belong to the same surface when they differ by
#: at most this fraction of the depth (:func:`morphkit.shadow.frame.render_frame`,
#: ``receiver_only``: pixels where the object alone gives the scene's depth are the
#: object's): linearised float32 depth buffers agree to ~1e-6 relative on one
#: surface, while the object and the ground under it are centimetres apart.
DEPTH_SAME_SURFACE_REL = 1e-4

#: The one-pass frame (:func:`morphkit.shadow.frame.render_frame`, issue #26) equals the
#: two-render frame within this mean absolute difference of ``shaded``, in levels of 255
#: (the issue's bound). Why not exactly: the one pass draws into a framebuffer object,
#: whose depth rounds differently from OSMesa's buffer (~1e-5 relative), so a shadow-edge
#: pixel's unprojected point, hence its visibility, can change; a textured fragment's
#: colour may round one level apart (:mod:`morphkit.render`, "One-pass frame").
FRAME_ONCE_MEAN_LEVELS = 1.0

#: ... and ``lit`` and ``unlit`` themselves differ by at most this many levels anywhere
#: (0 for untextured items; 1 seen on textured ones).
FRAME_ONCE_COLOR_LEVELS = 1

#: The compiled drawn-pixel kernel (:mod:`morphkit.shadow.pixels`) against its numpy reference
#: (:meth:`~morphkit.camera.CameraModel.unproject`): world points agree within this (scene units).
#: Same formula, but numpy's matrix product sums in BLAS's order (with fused multiply-adds), so the
#: last float64 bit or two differ: ~1e-15 on unit-size scenes a few units from the camera.
DRAWN_POINTS_ABS = 1e-12

#: ... and unit normals within this: both compute them in float32 from the float32 points, the same
#: operations in the same order; a float64 point one bit apart can round to a neighbouring float32
#: (~6e-8 relative), which moves a normal by that over the pixel's central difference.
DRAWN_NORMALS_ABS = 1e-5

#: The one-draw G-buffer (:meth:`morphkit.render.Renderer.gbuffer_pass`, issue #26) and the
#: three-draw passes (:meth:`~morphkit.render.Renderer.passes`): albedo differs by at most this
#: many levels anywhere (0 for untextured items; 1 seen on textured ones: a framebuffer object
#: rounds differently from OSMesa's buffer, :mod:`morphkit.render`, "One-pass frame and G-buffer").
#: Coverage is identical; depth agrees within :data:`DEPTH_SAME_SURFACE_REL`.
GBUFFER_ALBEDO_LEVELS = 1

#: ... and a :class:`~morphkit.sunlit.litmesh.LitMeshMode` frame shaded from either equals
#: the other within this mean absolute difference of ``rgb`` (all pixels and channels), in
#: levels of 255 (the issue's bound, as :data:`FRAME_ONCE_MEAN_LEVELS`).
GBUFFER_FRAME_MEAN_LEVELS = 1.0

#: Depth (scene units) added on each side of the object's depth range for a light
#: camera's near and far planes (:class:`~morphkit.shadow.rig.LightRig`, on top of
#: its relative ``margin``): keeps ``znear < zfar`` for an object of no depth
#: extent (a flat plate facing the light); a millimetre on the unit-size sample
#: meshes, far below a depth texel's worth of anything they show.
LIGHT_DEPTH_PAD = 1e-3

#: An object position (world units) is unchanged by clamping it into the motion
#: range when it moved by at most this (:meth:`morphkit.shadow.rig.LightRig.resolve`
#: warns otherwise). Clipping an inside position returns it exactly, so this is
#: only float64 noise; a position outside by more gets the
#: :class:`~morphkit.shadow.rig.RangeClampWarning`.
POSITION_EQUAL = 1e-12

#: Slack, relative to the far plane, by which a dome asset or sun atlas file's drawn depths may lie
#: outside its views' near and far planes (``read_dome``, ``read_sun_atlas``): they are stored in
#: float16 relative to the camera distance, which rounds them to 2**-11 of their size (at most the
#: far plane); 2**-10 is twice that, and far below a depth that draws something else.
DOME_DEPTH_SLACK_REL = 2.0**-10

# --- sun atlases (morphkit.sunlit.sunatlas) ----------------------------------
#: The grazing cut-off (degrees above the horizon) of a sun atlas's light views
#: (:mod:`morphkit.sunlit.sunatlas`): a sun between the horizon and this elevation is
#: served as if it stood at this elevation (clamped, not refused, so shadows do not
#: pop out while the sun sets). Below 5 degrees a shadow is over 11 object heights
#: long (``1 / tan 5``) and the ground it falls on gets ``sin 5 = 0.087`` of the
#: sun's noon light, while the light view's depth of a ground point changes by
#: ``cot e`` texels per texel, so the lookup grows as unreliable as the shadow grows
#: invisible. At or below the horizon there is no light view at all (no shadow).
SUN_MIN_ELEVATION_DEG = 5.0

#: Depth bias (light-view texels, constant, no slope term) of a ground point looked
#: up in a sun atlas's light view (:func:`morphkit.sunlit.sunatlas.ground_visibility`).
#: The ground is not drawn into the map, so it cannot shadow itself (no acne, no
#: slope term needed); what the bias absorbs is the morphed depth's own error, a
#: crossing refined by a secant and two bisections of a march step of about two
#: texels (:mod:`morphkit.views.depthmorph`), so about half a texel: one texel
#: covers it and loses at most a texel of contact shadow where the caster meets the
#: ground.
SUN_GROUND_BIAS_TEXELS = 1.0

#: The least absolute cosine between a splatted point's normal and its atlas view's direction in
#: its footprint's foreshortening (:mod:`morphkit.sunlit.fieldsplat`): texels the view sees
#: at a grazing angle (an estimated normal within 6 degrees of the image plane) are not
#: taken to stand for more surface than that.
SPLAT_MIN_COS = 0.1

#: The largest side, in field light-view texels, of the atlas point level an instance is
#: splatted at (:func:`morphkit.sunlit.fieldsplat.splat_levels`): an instance whose atlas texel
#: covers ``f`` field texels is drawn from blocks of ``2**l`` atlas texels with
#: ``2**l * f`` at most this. At 1 a level's point is never wider than the field's texel, so
#: the shadow's outline moves by under a field texel (the map cannot hold a finer one); a
#: field as fine as its atlases (``f`` near 1) keeps every point. Of 0.5, 0.71, 1 and 1.5 (the
#: ``bench scene`` fields of 10, 100 and 1000 instances at a quarter of the suite's resolution,
#: ground IoU against the ray cast), 1 kept level 0's IoU at 100 and 1000 instances with the
#: fewest points, 1.5 lost some at 10 (its coarse blocks' outlines are a field texel and a half).
SPLAT_LEVEL_MAX_TEXELS = 1.0

#: A block of a coarser atlas point level (:func:`morphkit.sunlit.pointlevels.block_points`)
#: is split into its front and its back where its drawn texels' depths differ by more than this
#: many block sides (object units: this times the block's side): a surface that steep across the
#: block (over about 55 degrees to the view's image plane along a diagonal) or two surfaces
#: apart. A split only adds a point (each part's centroid is on a flat surface); a gap too large
#: would put a point between a leaf and what lies behind it.
SPLAT_LEVEL_DEPTH_GAP = 2.0

#: A sun atlas view's quad (four drawn texels meeting at a corner,
#: :func:`morphkit.sunlit.pointlevels.grid_quads`) is drawn as two triangles when its four depths
#: lie within this many atlas texels of each other: a surface up to about 77 degrees from the
#: view's image plane along a diagonal; steeper ones and depth edges keep their squares (the
#: other views see them better). Of the gaps tried, 3 / 6 / 12, 6 gave the best surface IoU on
#: the scene suite's fields at 128, 256 and 512 texels (docs/results/field_shadows.md, "The
#: instances' own surfaces by resolution"); 3 cuts curved surfaces the views see obliquely into
#: squares again, 12 joins a leaf to what lies behind it.
SPLAT_QUAD_DEPTH_GAP = 6.0

#: An instance pose's rotation is a turn about ``+z`` (a yaw, what a sun atlas serves)
#: when its third column, divided by the pose's uniform scale, is ``+z`` to within
#: this (absolute) and its columns are orthonormal to :data:`POSE_ORTHO`: poses
#: built from a yaw in float64 are ~1e-16 off.
SUN_YAW_ONLY_ATOL = 1e-6

#: A texel of a sun atlas's morphed light view holds the caster where the morph's
#: coverage (the weighted vote of the three views: hit 1, free 0, occluded abstains;
#: :func:`morphkit.views.depthmorph.combine`) is at least this. The morph's own rule
#: (covered where any view hit) is the union of three silhouettes, each off by up to
#: half a texel either way, so it grows the shadow: on the tree (8 suns at 37 degrees'
#: yaw, ground grid against the ray cast) it shadowed 4.2x as many ground points
#: wrongly as it missed at 64 texels; a majority (0.5) brings that to 1.6x with the
#: fewest wrong points of the cuts tried (0.02, 0.5, 0.65, 0.8). With continuous
#: crossings only, 0.5 still has the fewest on the tree and the cow at
#: 64 and 128 texels (0.65: about as many, fewer extra and more missing).
SUN_VIEW_MIN_COVERAGE = 0.5


# --- a billboard scene's shadow receivers (morphkit.sunlit.receivers) ---------------
#: How far (field light-view texels) a shadow receiver that is drawn into the field's map
#: itself -- a billboard's pixel, a real mesh's pixel, from their depth -- is moved along
#: its own normal before the lookup (normal-offset bias). The field's lookup has only a
#: constant bias (:data:`SUN_GROUND_BIAS_TEXELS`, right for the ground, which is never in
#: the map), but a caster's surface compared with its own map entry differs by up to
#: ``tan(theta)`` texels across a texel at an angle ``theta`` to the light, plus the two
#: morphs' depth errors (the billboard's view and the atlas's light view, each about half
#: a texel): without an offset a billboard's sunlit side speckles with its own shadow
#: (acne). Of the offsets tried (0, 1, 2, 3 texels), 1 gave the best billboard-pixel shadow
#: IoU against the ray-cast mesh frame under each of three suns (20 trees and cows;
#: scripts/billboard_shadow_bench.py --offsets 0,1,2,3): 0 leaves the acne, larger ones
#: lose the shadows that fall across a billboard from a neighbour close by.
SUN_RECEIVER_NORMAL_OFFSET_TEXELS = 1.0

#: Largest side (texels) of a billboard frame's field light view when its resolution is
#: chosen automatically (:class:`morphkit.sunlit.receivers.AtlasShadow`): a float32 map
#: of 16 MiB, built (``np.full`` and one warp per caster) in a few ms; a wider field gets
#: coarser texels rather than a larger map.
SUN_FIELD_MAX_SIDE = 2048

#: ``billboards --sun-atlas-size``: the sun atlas views' side, texels. Under 16 an asset is a few
#: texels across; over 1024 an atlas of 21 views takes 66 MB (3 bytes a texel) and a frame's
#: field map (at most :data:`SUN_FIELD_MAX_SIDE` a side) no longer resolves it (docs/RESULTS.md).
MIN_SUN_ATLAS_SIZE, MAX_SUN_ATLAS_SIZE = 16, 1024

#: Most sun directions over a soft sun's disc (``--soft N``): one field map (or one ray
#: cast) each, per frame.
MAX_SUN_SAMPLES = 64

#: Widest blocker search and kernel, half-width in field texels, of a sun disc's filtered
#: lookup (:mod:`morphkit.sunlit.sundisc`): a wider penumbra is clipped to it (its edge then
#: too sharp). At the field's usual 64-128 texels an asset, 16 texels is an eighth to a
#: quarter of an instance, a 2-degree disc's penumbra 3 units behind its occluder; the cost
#: per point grows with the square (a 33 x 33 box: about 1,100 reads).
SUN_DISC_MAX_HALF_TEXELS = 16.0

#: Half-width (field texels) of the box a sun disc's filtered lookup widens its kernel by
#: (:mod:`morphkit.sunlit.sundisc`; a disc of nonzero radius only): the map holds an
#: occluder's edge only to the texel (a texel is drawn when its centre is covered), so the
#: true edge lies anywhere within half a texel either way of the drawn one, and at the real
#: sun (0.267 degrees) the disc's own penumbra is mostly narrower than that. The kernel is
#: the disc's square convolved with this box (a trapezoid a side), so the penumbra is never
#: narrower than half a texel and never falls back to the hard lookup. The mean estimate of
#: that edge would take 0.5 (the whole uncertainty), the error-minimising one in the mean
#: absolute sense 0 (the disc's square alone, centred on the drawn edge); measured on both
#: benches' fields (scripts/sun_disc_bench.py, morphkit bench scene --sections sun-disc;
#: 0, 0.1, 0.15, 0.2, 0.25, 0.3, 0.5 tried), the mean error is flat (within 3e-4) from 0
#: to 0.3 and 1e-3 to 3e-3 higher at 0.5, while the banding measure falls with the width:
#: 0.25 is the widest on the flat part.
SUN_DISC_RASTER_HALF_TEXEL = 0.25

#: Texels per unit of a filtered sun disc's one field map over the atlases' own (its default
#: resolution, :class:`morphkit.sunlit.receivers.FilteredAtlasShadow`; still capped by
#: :data:`SUN_FIELD_MAX_SIDE`). At the field's native resolution the filtered map's error at
#: the real sun (0.267 degrees) stays above that of 4 maps averaged over the disc, however
#: it is filtered: its edges lie on a texel grid that 4 slightly turned maps dither. The
#: atlases' points carry their positions below a texel, so a finer field map draws the edges
#: finer, for less than a second map's cost (the splat grows with its texels). Measured on
#: both benches' fields at 1, 1.5 and 2 (scripts/sun_disc_bench.py, morphkit bench scene
#: --sections sun-disc): 1.5 brings the real sun's error under 4 native maps' (and 16's) in
#: all four cases in under two thirds of 4 maps' time; 2 lowers it a little further (1-14 %)
#: for 1.3-1.9x the cost of the 1.5 map, and loses more at a 4-degree disc under a low sun,
#: where 1.5 already loses some (the kernel's cap, :data:`SUN_DISC_MAX_HALF_TEXELS`, is in
#: texels: a finer map clips wide penumbrae sooner; a cap scaled with the map was mixed).
SUN_DISC_MAP_SCALE = 1.5

#: Directions over the disc of the ray-cast truth beside a filtered soft sun
#: (``morphkit billboards --soft pcss``: its comparison strips): the truth of a disc needs
#: several directions, and a frame's ray cast costs one pass per direction; 16 is within
#: about 0.01 mean visibility of 64 over 1-4 degree discs (``scripts/sun_disc_bench.py``:
#: 32 against 64 directions 0.009).
SUN_DISC_TRUTH_SAMPLES = 16

#: Largest angular radius (degrees) of a soft sun's disc: a larger one is an area light
#: over a quarter of the sky, outside what a sun disc (a narrow cone) stands for.
MAX_SUN_DISC_DEG = 15.0

#: How far (scene units; the assets are normalised to unit size) the ray-cast truth moves a
#: real mesh's pixel point along its normal before casting towards the sun
#: (:class:`morphkit.sunlit.receivers.RayCastShadow`): the point comes from the depth pass
#: (24-bit window depth, linearised), up to about 1e-3 units off its surface at the frames'
#: distances, so rays from it hit its own triangle and speckle a sunlit surface with
#: shadow; :data:`RAY_OFFSET` (along the ray) is too small for that. Twice the error.
SUN_RAY_NORMAL_OFFSET = 2e-3

#: The alpha test of an impostor card drawn into a shadow map
#: (:mod:`morphkit.sunlit.cardbaselines`): a texel of the card casts where the frame's
#: coverage, bilinearly sampled as a GPU samples the card's texture, is at least this --
#: the engines' default clip value (glTF's ``alphaCutoff``, Unreal's masked 0.5), which
#: keeps a silhouette whose coverage ramps over a texel at its middle.
IMPOSTOR_CARD_ALPHA_TEST = 0.5

#: Margin (pixels) around a stretched reprojected quad's drawn triangles within which the
#: reprojection tests pixel centres (:mod:`morphkit.shadow.reprojection.kernels`), not its
#: whole box: a centre the barycentric test takes lies within ``2 *`` :data:`MESH_BOUNDARY_PX`
#: times a triangle's extent (at most the stretch limit, 4 px: 8e-6 px) of its vertices'
#: box, plus the test's rounding (~1e-12 px for triangles of at least
#: :data:`REPROJECT_SLIVER_AREA2_PX2`); 1e-3 is ~100x that, so no write changes.
REPROJECT_DRAWN_BOX_PX = 1e-3

#: A reprojected triangle with twice its area (pixels^2) under this is a sliver whose
#: barycentric rounding is not bounded by :data:`REPROJECT_DRAWN_BOX_PX`: its quad keeps
#: its whole box.
REPROJECT_SLIVER_AREA2_PX2 = 1e-2


#: A frame pixel shows the ground (``z = 0``) when its unprojected point lies within this of the
#: plane (scene units; the playback scene's object is normalised to size 1): above the depth
#: buffer's error at the playback distances (~1e-4), below any part of an object standing on it.
GROUND_PIXEL_DZ = 1e-3
