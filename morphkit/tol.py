"""Numerical tolerances, in one place (as trimesh does).

Every threshold morphkit uses to decide that something is degenerate, equal or
valid lives here, with the reason for its value. Tests import these rather than
repeating numbers.
"""

from __future__ import annotations

#: Smallest absolute signed area (pixels^2) of a warp triangle that still counts as a
#: triangle: a smaller one maps its whole source onto a point.
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

#: Distance (scene units) a ray-cast shadow's origin is pushed towards the light, so that a point on
#: the occluder's surface does not hit itself: far above Embree's float32 rounding and far below a
#: shadow-map texel on the unit-size sample meshes (derived: docs/results/tolerances.md).
RAY_OFFSET = 1e-4

#: Most casts of a shadow ray through cut-out holes (masked leaf-card texels), each from
#: :data:`RAY_OFFSET` past the last hit (:func:`morphkit.imaging.groundtruth.hard_visibility`); a ray
#: still in holes counts as shadowed, with a :class:`~morphkit.imaging.groundtruth.CutoutLayersWarning`.
#: Far above a plant's few tens of leaf layers, it only stops a grazing ray re-hitting one card.
CUTOUT_MAX_LAYERS = 64

#: Outward margin (pixels) of a warp's destination mesh boundary when deciding which output pixel
#: centres it covers, so that centres on the boundary (an identity warp's last row and column) are
#: covered: far above coordinate rounding, far below a visible shift (derived: docs/results/tolerances.md).
MESH_BOUNDARY_PX = 1e-6

#: Largest vertex coordinate (scene units, absolute) of a mesh morphkit reads: well below where
#: trimesh's int64 vertex hashing overflows, and beyond any real model (derived: docs/results/tolerances.md).
MESH_MAX_COORD = 1e9

#: Most nodes of a glTF file morphkit reads (:mod:`morphkit.meshes.gltf`, checked on its JSON before
#: trimesh reads it): trimesh's read time grows with the node count, and an asset of this many parts is
#: already a scene, not an object (measured: docs/results/tolerances.md).
MAX_GLTF_NODES = 10_000

#: A glTF scene's instance stands on the ground (:func:`morphkit.scenes.gltfscene.read_gltf_scene`) when
#: the base of its asset lies within this fraction of the asset's size of ``z = 0``: far above the float32
#: rounding of an exporter's vertices and node translations, far below a visible float (a millimetre on a
#: metre-tall asset); one further off is set on the ground, with a note.
GLTF_GROUND_REL = 1e-3

#: Relative length below which a mesh counts as flat in a direction (:func:`morphkit.meshes.check_mesh`:
#: second principal or bounding-box extent over the first): far above coordinate rounding, far below
#: any real feature (a nanometre on a one-metre object).
MESH_ZERO_LENGTH_REL = 1e-9

#: A mesh face whose area is below this times the mesh's squared largest extent has zero area
#: (:func:`morphkit.meshes.check_mesh`; a mesh of only such faces is refused): far above the rounding
#: of a float64 cross product (derived: docs/results/tolerances.md).
MESH_ZERO_AREA_REL = 1e-12

#: Slack (UV units, texture widths) within which a UV counts as on an integer when counting a part's
#: texture repeats (:func:`morphkit.meshes.parts.merge_parts`), so that exporters' float noise adds no
#: whole repeat; it is a fraction of a texel at any supported texture size.
UV_TILE_SLACK = 1e-6

#: Central-difference step (metres, before normalisation) of the implicit sample shapes' field gradient
#: (:func:`morphkit.meshes.implicit.project`): far below the shapes' smallest feature and far above the
#: field's float64 rounding, so the quotient is the gradient (derived: docs/results/tolerances.md).
SDF_GRADIENT_STEP = 1e-4

#: Floor of the squared field gradient in that projection, so a point where the gradient vanishes
#: (the medial axis) is not divided by ~0: near the surface the gradient's norm is ~1, so it never
#: changes a real step.
SDF_GRADIENT_FLOOR = 1e-12

# --- generic zeros and equalities (one name each, instead of bare epsilons) ---

#: A float64 magnitude at or below this is zero (the floor of a divisor: a norm, determinant or
#: weight): it only catches exact or underflowed zeros, so it never changes a real quotient.
ZERO = 1e-300

#: Two float64 quantities of one scale are equal when they differ by less than this times that scale
#: (coordinates, depths, grid parameters): far above accumulated float64 rounding, far below any
#: difference a user could mean (a nanometre in a metre).
REL_EQUAL = 1e-9

#: Two pixel coordinates (or control points, in pixels) are the same point when they differ by at
#: most this many pixels: a shift this small moves no sample visibly.
PX_EQUAL = 1e-6

#: Floor of a float32 alpha or accumulated weight that colour is divided by (to leave premultiplied
#: form or normalise a weighted sum); below it a pixel is transparent, as it is far below one 8-bit step.
ALPHA_FLOOR = 1e-6

#: A visibility within this of 0 or 1 is umbra or lit, not penumbra, in the soft-shadow bench's banding
#: measure (:func:`morphkit.bench.soft_suite.banding`; :mod:`morphkit.sunlit.sundisc` returns such values
#: as 0 or 1): it absorbs the round-off of summed lookups, so the measure does not move with summation order.
PENUMBRA_EPS = 1e-6

#: Two unit vectors are parallel when ``abs(dot) > 1 - PARALLEL_DOT`` (about 0.08 degrees): a look-at
#: up vector, a light along an axis; nearer than that their cross product's direction is ill-conditioned.
PARALLEL_DOT = 1e-6

# --- light cameras fitted to points (morphkit.scene.light_view) --------------

#: Nearest a fitted orthographic light camera's near plane may be (scene units), so that it stays
#: positive (CameraModel refuses znear <= 0) when the points reach the camera: far below any feature.
LIGHT_FIT_MIN_ZNEAR = 1e-3

#: Depth (scene units) added on both sides of the points' depth range of a fitted perspective light
#: camera, so that points all at one depth still get ``zfar > znear * (1 + REL_EQUAL)``: too small
#: to change a depth a 24-bit buffer stores.
LIGHT_FIT_DEPTH_PAD = 1e-6


# --- size limits (checked before anything is allocated) ---------------------

#: Bytes of memory per pixel that an offscreen GL context and its first draw take (checked before the
#: context is created: :mod:`morphkit.render`), so that Mesa refuses rather than dies of a failed
#: allocation: llvmpipe's peak plus a third (measured: docs/results/tolerances.md).
GL_BYTES_PER_PIXEL = 48

#: Bytes of memory per pixel a context's first one-pass frame draw adds (checked before each:
#: :meth:`morphkit.render.Renderer.frame_pass` and ``gbuffer_pass``): llvmpipe's rise at that draw
#: plus a third (measured: docs/results/tolerances.md).
GL_FRAME_PASS_BYTES_PER_PIXEL = 40

#: Most pixels an image, depth map or render may have (8192 x 8192; more is a ``ValidationError``
#: from :func:`morphkit.validate.as_shape` before any allocation): a frame's several per-pixel
#: buffers then take a few GB (derived: docs/results/tolerances.md).
MAX_IMAGE_PIXELS = 2**26

#: Most bytes one array morphkit allocates for the caller's sizes may take (4 GiB): enough for the
#: largest one, a shadow atlas's maps, at a 3 x 3 atlas of 8192^2 maps.
MAX_BUFFER_BYTES = 2**32

#: Most texels one texture may have (4096 x 4096; downscale a larger one): the renderer keeps it as
#: RGBA mipmaps per GL context besides the numpy copy, and real-time assets rarely exceed it per material.
MAX_TEXTURE_PIXELS = 4096 * 4096

#: Most texels on one side of a texture: below the 16384 that llvmpipe (OSMesa) and recent desktop
#: GPUs allow, while a 8192 x 2048 strip still fits :data:`MAX_TEXTURE_PIXELS`.
MAX_TEXTURE_SIDE = 8192

#: Largest side (pixels) of a video morphkit writes (``shadows.webm``, ``billboards.webm``, ``.mp4``),
#: checked before any frame is rendered: ``mp4v`` stores the side in 13 bits and FFmpeg refuses 8192.
MAX_VIDEO_SIDE = 8190

#: Most frames one command renders along a path (``shadows``, ``billboards``, ``viewmorph --frames``):
#: an hour of video at 25 fps, as each frame is a file and the frame list is built up front.
MAX_FRAMES = 100_000

#: Most billboard instances one scene places (``morphkit billboards --n``): instances are placed up
#: front and drawn one by one, and the paper's forest scenes have a few thousand.
MAX_INSTANCES = 100_000

#: Most reference views of one billboard asset (as :class:`morphkit.bake.BillboardKind` allows): beyond
#: it neighbouring views are under 6 degrees apart and a morph between them looks like either.
MAX_BILLBOARD_VIEWS = 64

#: Largest reference view side of a billboard asset, pixels (as
#: :class:`morphkit.bake.BillboardKind` allows): 64 views of 2048^2 RGBA with their
#: mip levels are already ~1.4 GB.
MAX_BILLBOARD_SIDE = 2048

#: Most local worker processes of a bake (``morphkit bake --workers``): each is a
#: Python process with its own GL context (~200 MB); 256 is beyond any single
#: machine's useful count.
MAX_LOCAL_WORKERS = 256

#: Most threads of a banded pass (``MORPHKIT_WARP_THREADS``): each takes a band of rows
#: and a stack of its own; beyond one a core, they only wait on each other.
MAX_WARP_THREADS = 256

#: Largest EGL device index (``MORPHKIT_EGL_DEVICE``): far beyond the GPUs of any one machine,
#: so that a typo (a port number, a PCI address) is refused rather than tried.
MAX_EGL_DEVICE = 1023

#: Most instances of one ``bench scene`` field (``morphkit bench scene --instances``): its
#: ``sun-change`` section poses all instances into one mesh, which at twice the suite's largest
#: default is what a machine of tens of GB holds (derived: docs/results/tolerances.md).
MAX_BENCH_INSTANCES = 2000

#: Most assets of the ``bench bake`` library (``morphkit bench bake --assets``): each is a mesh file
#: written to a temporary folder and baked once per phase; 16x the 256 assets the suite's
#: projection targets.
MAX_BENCH_ASSETS = 4096

#: Largest seed a command takes (``billboards --seed``): numpy's generators take any
#: non-negative integer; one that fits 64 bits is what a user can write down and repeat.
MAX_SEED = 2**64 - 1

#: Most light samples of an area light (``n_u * n_v``, or rows of an explicit sample array): the
#: visibility step ``1 / N`` is then far finer than one 8-bit level, so more samples only cost maps.
MAX_LIGHT_SAMPLES = 4096

#: Half-width (texels) below which a filtered shadow lookup's kernel is the hard lookup, and the least
#: half-width of a wider one (:mod:`morphkit.shadow.filtering.filtered`): a narrower box only blurs the
#: map's own texel edges, and the hard lookup gives a light of zero extent its hard shadow exactly.
PENUMBRA_MIN_HALF_TEXEL = 0.5

#: Largest ``|x|`` or ``|y|`` (pixels) of a mesh warp's control points (:mod:`morphkit.warp`; beyond it
#: a ValidationError): any mesh reaching off an image fits, and float64 still resolves an edge crossing
#: there (derived: docs/results/tolerances.md).
MAX_COORD_PX = 1e7

# --- view morphing (morphkit.viewmorph) -------------------------------------

#: Default inlier threshold (pixels) of the robust fundamental-matrix fit (Sampson distance) and of
#: the homography-degeneracy test (transfer distance): above SIFT's sub-pixel keypoint error, so good
#: matches stay while gross outliers go.
VM_THRESHOLD_PX = 1.0

#: Points whose centred scatter has singular values s2 / s1 below this ratio are
#: collinear: a 1000:1 elongated cloud leaves F (and any homography) undetermined
#: in the short direction at the noise levels above.
VM_COLLINEAR_RATIO = 1e-3

#: Two pairs closer than this (pixels, in either image) are duplicates; the later
#: one is dropped. Closer points only make sliver triangles in the morph mesh.
VM_DUPLICATE_PX = 1e-3

#: The pairs are "explained by a homography" (planar scene, pure rotation, zero baseline, identical
#: images; F = [e1]x H is then undetermined) when its inliers reach this fraction of F's at the same
#: threshold: 5% leaves room for the few off-plane points a robust F fit would otherwise be built on.
VM_HOMOGRAPHY_INLIER_RATIO = 0.95

#: An epipole whose homogeneous w is below this fraction of the norm of (x, y) is at
#: infinity (a 1e-9 relative w puts it ~1e9 image widths away).
VM_EPIPOLE_INFINITY = 1e-9

#: The views are already parallel (rectified; the pre-warp is skipped) when the
#: inlier pairs' RMS vertical disparity y1 - y0 is at most this (pixels): below
#: half a pixel a rectification would move points by less than its resampling blur.
VM_PARALLEL_Y_PX = 0.5

#: A component of a unit-norm vector or matrix of the view-morph geometry (an epipole's in-plane
#: direction, an epipolar line's direction, a pre-warp's Jacobian row) below this is zero: far above
#: SVD's float64 accuracy, so only true degeneracies (an epipole on the optical axis) are caught.
VM_UNIT_ZERO = 1e-12

#: Seitz & Dyer's rotated (unit-norm) F must reach the form [[0,0,0],[0,0,a],[0,b,c]], its other
#: entries at most this: room for F's conditioning over the rotations' float64 rounding, while any
#: F the construction did not rectify is refused.
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

#: Relative depth tolerance of the geometric correspondences' visibility test (a point is visible if its
#: depth is at most (1 + rtol) times the rendered depth around its projection): above depth quantisation
#: and one pixel's slope, below the gap between a surface and what it hides (derived:
#: docs/results/tolerances.md).
VM_VISIBILITY_RTOL = 0.01

#: Smallest absolute signed area (pixels^2) a morph-mesh triangle may reach for any s in [0, 1]; smaller
#: ones are fold-overs and a vertex is dropped: 1000x the warp's own refusal limit (tol.TRIANGLE_AREA_PX2),
#: so float32 maps never meet it.
VM_MIN_TRIANGLE_AREA_PX2 = 1e-3

#: Overlap of a layered morph's depth layers (``ViewMorpher(layers=k)``), as a fraction of the pairs'
#: depth range, so that a surface cut by a layer edge is drawn by both and no cracks open at the cut;
#: more overlap drags the far side into the near layer (measured: docs/results/tolerances.md).
VM_LAYER_OVERLAP = 0.02

#: The depth layers' 1-D k-means stops when no centre moved by more than this times the largest depth
#: magnitude (at least 1): that is converged to float64 rounding, far finer than any pixel's depth difference.
VM_KMEANS_CONVERGED_REL = 1e-12

#: Fewest distinctive (SIFT) matches two images must share for ``morphkit viewmorph`` to take them for
#: views of one scene when it finds the correspondences itself: dense flow matches any two images, so only
#: these can tell, and fewer than the 8 pairs F needs (:func:`morphkit.viewmorph.plan_view_morph`) cannot.
VM_MIN_SCENE_MATCHES = 8

#: Smallest side (pixels) of the images DIS optical flow runs on (``FlowMatcher`` pads smaller ones
#: with zeros): the smallest size at which no OpenCV DIS preset refuses or crashes (measured:
#: docs/results/tolerances.md).
VM_FLOW_MIN_SIDE = 32

#: Fewest pairs a depth layer may hold; with fewer, the layer count drops (the
#: fallback is reported in ``ViewMorpher.report.layers``). 8 is the pair count F needs,
#: and a layer's mesh needs its own pairs to move differently from its neighbours.
VM_MIN_LAYER_PAIRS = 8

#: Most pairs, spread over image 0, of the least-squares homography of a post-warp to a target camera:
#: a fraction of the time of all the dense pairs for nearly the same residual (measured:
#: docs/results/tolerances.md).
VM_POST_FIT_PAIRS = 256

#: ``ViewMorpher(layers="auto")`` layers the morph when the single mesh dropped more than this fraction
#: of its pairs to fold-overs: below it a second layer costs smooth meshes a little, above it it gains
#: much (measured: docs/results/tolerances.md).
VM_AUTO_LAYER_DROP = 0.005

#: How many layers ``layers="auto"`` uses when it layers: two take crossing parts apart and a third
#: adds time, not accuracy (measured: docs/results/tolerances.md).
VM_AUTO_LAYERS = 2

# --- billboard assets (morphkit.billboard) ----------------------------------

#: Fewest correspondences (from the two depth maps, before cleaning) neighbouring reference views must
#: share to be baked into an asset: 4x the 8 pairs F needs gives the robust fit a margin, and a morph
#: mesh with fewer points cannot follow an object's outline.
BB_MIN_CORRESPONDENCES = 32

#: Depth tolerance of the bake's visibility test, in bounding radii of the mesh
#: (``from_depth(rtol=BB_VISIBILITY_RADII / distance_factor)``): unlike :data:`VM_VISIBILITY_RTOL` it does
#: not grow with the bake distance until hidden points (a chair's far legs) count as visible and fold over.
BB_VISIBILITY_RADII = 0.04

#: Splat grid of a morph's coverage from depth (:func:`morphkit.billboard.splat_coverage`),
#: per image pixel and axis: 2 gives anti-aliased edges (4 levels of coverage per
#: pixel) at a quarter of the cost of 4.
BB_COVERAGE_SUPERSAMPLE = 2

#: Closing (fine-grid pixels) of the coverage splats: the smallest that closes the gaps between
#: neighbouring reference pixels in in-between views (measured: docs/results/tolerances.md).
BB_COVERAGE_CLOSE_PX = 5

#: A morph pixel with alpha at or below this carries no usable colour (its
#: un-premultiplied colour is noise): the coverage from depth is not applied there.
BB_COVERAGE_MIN_ALPHA = 0.02

#: Absolute tolerance within which an asset file's stored reference cameras (``K`` in pixels,
#: ``cam2world`` in scene units) must match the camera rule's recomputed ones: both come from the same
#: float64 numbers through exact JSON, so a larger difference means an edited or foreign file.
BB_FILE_CAMERA_ATOL = 1e-9

#: A viewing direction's octahedral grid coordinate within this of an integer is on that grid line
#: (:meth:`~morphkit.billboard.impostor.OctahedralImpostor.weights`), so that a frame's own direction,
#: rebuilt ~1e-15 off its grid point, is served by that frame alone (weight exactly 1).
IMP_GRID_SNAP = 1e-9

#: Floor of the cosine between a viewing direction and a frame's direction when an octahedral impostor
#: intersects the viewing ray with the frame's plane: only a 3 x 3 grid's top frame, at zero weight,
#: reaches 90 degrees, and the floor keeps it from dividing by zero (derived: docs/results/tolerances.md).
IMP_MIN_COS = 1e-3

# --- billboard scenes (morphkit.billboard) ---------------------------------

#: A camera is "directly above" a billboard (facing and viewing azimuth undefined; the fallback is in
#: :mod:`morphkit.billboard.frames.facing`) when its horizontal distance is below this fraction of the
#: full distance: there the quad would spin arbitrarily for a tiny camera move (derived:
#: docs/results/tolerances.md).
BB_ABOVE_RATIO = 1e-6

#: How far (degrees) above a ring asset's reference elevation (:class:`~morphkit.billboard.ring.ViewRing`)
#: its views still serve an eye (:meth:`ViewRing.band_deg`; higher, ``morphkit billboards`` takes dome views):
#: the axial quads' missing top and foreshortened sides stay unseen on the pan, orbit and fly paths.
BB_RING_BAND_DEG = 20.0

#: A billboard quad whose screen projection covers less than this area (pixels^2) is skipped (an axial
#: quad seen edge-on, with a near-singular homography): half a pixel of area holds at most one pixel centre.
BB_MIN_AREA_PX2 = 0.5

#: A backdrop ray hits the ground plane ``z = 0`` only when its unit direction points
#: down by more than this (``dz < -BB_GROUND_RAY_DZ``); rays closer to horizontal
#: (the horizon row at most) show the sky, so the hit distance ``-z / dz`` stays finite.
BB_GROUND_RAY_DZ = 1e-12

#: A billboard pixel goes under the frame's depth buffer (:mod:`morphkit.billboard.frames.compositor`)
#: only when behind it by more than this fraction, so that surfaces that meet keep the plain
#: back-to-front "over" instead of flipping with the last bits of their depths.
BB_DEPTH_REL = 1e-5
#: A billboard pixel writes the depth buffer from this alpha on: the coverage measures'
#: silhouette threshold, so that a faint anti-aliased rim hides nothing behind it.
BB_DEPTH_OPAQUE_ALPHA = 0.5
#: Draws of a new position for an instance whose footprint meets another's
#: (:func:`morphkit.billboard.frames.instances.separate`) before it is counted as crowded: a free
#: place is found in a few draws until the field is nearly full.
BB_SCATTER_TRIES = 100

#: Largest forward-backward disagreement (pixels) of a dense optical-flow pair
#: (:class:`~morphkit.viewmorph.matching.FlowMatcher`): DIS flow is sub-pixel where right and off by pixels
#: at occlusions, and this is F's inlier threshold (:data:`VM_THRESHOLD_PX`), so no kept pair is an outlier.
VM_FLOW_FB_PX = 1.0

#: An estimated F whose pre-warps are refused (epipole in or near an image, or too distorting) is
#: replaced by the affine F when that keeps at least this fraction of the general F's inliers: the views
#: are then nearly affine and the general F's epipole fits noise (measured: docs/results/tolerances.md).
VM_AFFINE_INLIER_RATIO = 0.6

#: ... and when, over the pairs both explain, the affine F's RMS Sampson distance is at most this many
#: times the general F's: F must halve the residual to count as determined, while a real epipole in the
#: image (exact pairs fit the general F orders of magnitude closer) stays refused.
VM_AFFINE_RMS_RATIO = 2.0

# --- shadow wing ---------------------------------------------------------------
#: A point projects through a light camera's texture matrix only when its homogeneous ``w`` (depth in
#: front of a point light, scene units; 1 for a directional light) exceeds this
#: (:func:`morphkit.shadow.lookup.shadow_visibility`): it only refuses points where ``x / w`` would blow up.
SHADOW_LOOKUP_W_MIN = 1e-12

#: Floor of the cosine between a receiver's normal and the light direction in the slope bias's
#: ``tan = sin / cos`` (:class:`~morphkit.shadow.lookup.ShadowBias`): it only keeps a grazing surface
#: from dividing by zero, as the tangent is clamped at ``ShadowBias.max_tan`` anyway.
SHADOW_GRAZING_COS = 1e-6

#: Two rendered depths of one pixel belong to one surface when they differ by at most this fraction of the
#: depth (:func:`morphkit.shadow.frame.render_frame`, ``receiver_only``): far above linearised depth
#: buffers' disagreement on one surface, far below the object-to-ground gap (derived:
#: docs/results/tolerances.md).
DEPTH_SAME_SURFACE_REL = 1e-4

#: The one-pass frame (:func:`morphkit.shadow.frame.render_frame`) equals the two-render frame within
#: this mean absolute difference of ``shaded``, in levels of 255: the frame's own rounding, as a
#: framebuffer object's depth rounds differently (:mod:`morphkit.render`, "One-pass frame").
FRAME_ONCE_MEAN_LEVELS = 1.0

#: ... and ``lit`` and ``unlit`` themselves differ by at most this many levels anywhere: the rounding of
#: a textured fragment (untextured items match exactly; measured: docs/results/tolerances.md).
FRAME_ONCE_COLOR_LEVELS = 1

#: World points of the compiled drawn-pixel kernel (:mod:`morphkit.shadow.pixels`) and of its numpy
#: reference (:meth:`~morphkit.camera.CameraModel.unproject`) agree within this (scene units): the same
#: formula, summed in a different order, differs in the last float64 bits (derived:
#: docs/results/tolerances.md).
DRAWN_POINTS_ABS = 1e-12

#: ... and unit normals within this: both compute them in float32 from the float32 points, so a float64
#: point one bit apart rounds at most to a neighbouring float32 (derived: docs/results/tolerances.md).
DRAWN_NORMALS_ABS = 1e-5

#: Albedo of the one-draw G-buffer (:meth:`morphkit.render.Renderer.gbuffer_pass`) and of the three-draw
#: passes (:meth:`~morphkit.render.Renderer.passes`) differs by at most this many levels (coverage
#: identical, depth within :data:`DEPTH_SAME_SURFACE_REL`): textured fragments round one level apart
#: (measured: docs/results/tolerances.md).
GBUFFER_ALBEDO_LEVELS = 1

#: ... and a :class:`~morphkit.sunlit.litmesh.LitMeshMode` frame shaded from either equals
#: the other within this mean absolute difference of ``rgb`` (all pixels and channels), in
#: levels of 255 (as :data:`FRAME_ONCE_MEAN_LEVELS`).
GBUFFER_FRAME_MEAN_LEVELS = 1.0

#: Depth (scene units) added on each side of the object's depth range for a light camera's near and far
#: planes (:class:`~morphkit.shadow.rig.LightRig`, on top of its ``margin``), so that a flat plate facing
#: the light keeps ``znear < zfar``: a millimetre on the unit-size meshes, below a depth texel's worth.
LIGHT_DEPTH_PAD = 1e-3

#: An object position (world units) is unchanged by clamping into the motion range when it moved by at
#: most this (:meth:`morphkit.shadow.rig.LightRig.resolve`; more gets a
#: :class:`~morphkit.shadow.rig.RangeClampWarning`): clipping an inside position returns it exactly, so
#: this is only float64 noise.
POSITION_EQUAL = 1e-12

#: Slack, relative to the far plane, by which a dome asset or sun atlas file's drawn depths may lie outside
#: its views' near and far planes (``read_dome``, ``read_sun_atlas``): twice the float16 storage's rounding
#: of 2**-11, far below a depth that draws something else.
DOME_DEPTH_SLACK_REL = 2.0**-10

# --- sun atlases (morphkit.sunlit.sunatlas) ----------------------------------
#: The grazing cut-off (degrees above the horizon) of a sun atlas's light views
#: (:mod:`morphkit.sunlit.sunatlas`): a lower sun is served as if at this elevation (at or below the
#: horizon: no shadow), since a shadow there is as unreliable in the lookup as it is invisible on the dim
#: ground (derived: docs/results/tolerances.md).
SUN_MIN_ELEVATION_DEG = 5.0

#: Constant depth bias (light-view texels, no slope term: the ground is not drawn into the map) of a
#: ground point looked up in a sun atlas's light view
#: (:func:`morphkit.sunlit.sunatlas.ground_visibility`): it covers the morphed depth's own error
#: (:mod:`morphkit.views.depthmorph`), about half a texel (derived: docs/results/tolerances.md).
SUN_GROUND_BIAS_TEXELS = 1.0

#: The least absolute cosine between a splatted point's normal and its atlas view's direction in
#: its footprint's foreshortening (:mod:`morphkit.sunlit.fieldsplat`): texels the view sees
#: at a grazing angle (an estimated normal within 6 degrees of the image plane) are not
#: taken to stand for more surface than that.
SPLAT_MIN_COS = 0.1

#: Largest side (field light-view texels) of the atlas point level an instance is splatted at
#: (:func:`morphkit.sunlit.fieldsplat.splat_levels`: blocks of ``2**l`` atlas texels with ``2**l * f`` at
#: most this): a point no wider than the field's texel, as wider blocks lost accuracy (measured:
#: docs/results/tolerances.md).
SPLAT_LEVEL_MAX_TEXELS = 1.0

#: A coarser atlas point level's block (:func:`morphkit.sunlit.pointlevels.block_points`) is split into front
#: and back where its drawn depths differ by more than this many block sides (a surface over about 55 degrees
#: steep, or two surfaces): a split only adds a point, a larger gap would put one between a leaf and its back.
SPLAT_LEVEL_DEPTH_GAP = 2.0

#: A sun atlas view's quad (four drawn texels meeting at a corner,
#: :func:`morphkit.sunlit.pointlevels.grid_quads`) is drawn as two triangles when its four depths lie
#: within this many atlas texels (a surface up to about 77 degrees steep): the gap with the best surface
#: IoU on the scene suite (measured: docs/results/tolerances.md).
SPLAT_QUAD_DEPTH_GAP = 6.0

#: An instance pose's rotation is a turn about ``+z`` (a yaw, what a sun atlas serves) when its third
#: column, divided by the pose's uniform scale, is ``+z`` to within this (absolute) and its columns are
#: orthonormal to :data:`POSE_ORTHO`: poses built from a yaw in float64 are ~1e-16 off.
SUN_YAW_ONLY_ATOL = 1e-6

#: A texel of a sun atlas's morphed light view holds the caster where the morph's coverage (the three views'
#: weighted vote, :func:`morphkit.views.depthmorph.combine`) is at least this: a majority, rather than the
#: union that grows the shadow, had the fewest wrong ground points (measured: docs/results/tolerances.md).
SUN_VIEW_MIN_COVERAGE = 0.5


# --- a billboard scene's shadow receivers (morphkit.sunlit.receivers) ---------------
#: Normal offset (field light-view texels) of a shadow receiver drawn into the field's map itself (a
#: billboard's or a real mesh's pixel) before the lookup: less lets a sunlit side speckle with its own
#: shadow, more loses a close neighbour's shadow (measured: docs/results/tolerances.md).
SUN_RECEIVER_NORMAL_OFFSET_TEXELS = 1.0

#: Largest side (texels) of a billboard frame's field light view when its resolution is chosen automatically
#: (:class:`morphkit.sunlit.receivers.AtlasShadow`): a float32 map of 16 MiB, built by ``np.full`` and one
#: warp per caster; a wider field gets coarser texels rather than a larger map.
SUN_FIELD_MAX_SIDE = 2048

#: ``billboards --sun-atlas-size``: the sun atlas views' side, texels: below, an asset is a few texels
#: across; above, an atlas takes tens of MB and a frame's field map (at most :data:`SUN_FIELD_MAX_SIDE`
#: a side) no longer resolves it (measured: docs/results/tolerances.md).
MIN_SUN_ATLAS_SIZE, MAX_SUN_ATLAS_SIZE = 16, 1024

#: Most sun directions over a soft sun's disc (``--soft N``): one field map (or one ray
#: cast) each, per frame.
MAX_SUN_SAMPLES = 64

#: Widest blocker search and kernel, half-width in field texels, of a sun disc's filtered lookup
#: (:mod:`morphkit.sunlit.sundisc`; a wider penumbra is clipped): an eighth to a quarter of an instance at
#: the field's usual resolution, as the cost per point grows with its square (derived:
#: docs/results/tolerances.md).
SUN_DISC_MAX_HALF_TEXELS = 16.0

#: Half-width (field texels) of the box a sun disc's filtered lookup convolves its kernel with
#: (:mod:`morphkit.sunlit.sundisc`; nonzero radius only), for the map's half-texel edge uncertainty: the
#: widest box before the mean error grows (measured: docs/results/tolerances.md).
SUN_DISC_RASTER_HALF_TEXEL = 0.25

#: Texels per unit of a filtered sun disc's one field map over the atlases' own (its default resolution,
#: :class:`morphkit.sunlit.receivers.FilteredAtlasShadow`; capped by :data:`SUN_FIELD_MAX_SIDE`): the
#: scale at which one filtered map beats a few native maps averaged at the real sun (measured:
#: docs/results/tolerances.md).
SUN_DISC_MAP_SCALE = 1.5

#: Directions over the disc of the ray-cast truth beside a filtered soft sun (``morphkit billboards --soft
#: pcss``: its comparison strips): 16 come close to 64's truth for a quarter of the ray-cast passes
#: (measured: docs/results/tolerances.md).
SUN_DISC_TRUTH_SAMPLES = 16

#: Largest angular radius (degrees) of a soft sun's disc: a larger one is an area light
#: over a quarter of the sky, outside what a sun disc (a narrow cone) stands for.
MAX_SUN_DISC_DEG = 15.0

#: Normal offset (scene units, unit-size assets) of a real mesh's pixel point before the ray-cast truth
#: (:class:`morphkit.sunlit.raycast.RayCastShadow`) casts towards the sun, where :data:`RAY_OFFSET` is too
#: small: twice the depth pass's error, so rays do not hit their own triangle (measured:
#: docs/results/tolerances.md).
SUN_RAY_NORMAL_OFFSET = 2e-3

#: The alpha test of an impostor card drawn into a shadow map (:mod:`morphkit.sunlit.cardbaselines`: a card's
#: texel casts where its bilinear coverage is at least this): the engines' default clip value (glTF's
#: ``alphaCutoff``, Unreal's masked 0.5), which keeps a ramped silhouette at its middle.
IMPOSTOR_CARD_ALPHA_TEST = 0.5

#: Margin (pixels) around a stretched reprojected quad's drawn triangles within which the reprojection
#: tests pixel centres (:mod:`morphkit.shadow.reprojection.kernels`), not its whole box: ~100x the bound
#: of :data:`MESH_BOUNDARY_PX` and rounding for triangles of at least :data:`REPROJECT_SLIVER_AREA2_PX2`,
#: so no write changes.
REPROJECT_DRAWN_BOX_PX = 1e-3

#: A reprojected triangle with twice its area (pixels^2) under this is a sliver whose
#: barycentric rounding is not bounded by :data:`REPROJECT_DRAWN_BOX_PX`: its quad keeps
#: its whole box.
REPROJECT_SLIVER_AREA2_PX2 = 1e-2


#: A frame pixel shows the ground (``z = 0``) when its unprojected point lies within this of the
#: plane (scene units; the playback scene's object is normalised to size 1): above the depth
#: buffer's error at the playback distances (~1e-4), below any part of an object standing on it.
GROUND_PIXEL_DZ = 1e-3

#: The planner's budget on a frame's predicted error (:func:`morphkit.plan.predict.predict_frame_error`):
#: the median gap to the measured one, in dB of box PSNR and in silhouette IoU, under which a choice made
#: from the error tables is one the frame keeps (a PSNR step of the morph over the card is several dB).
PLAN_GAP_DB = 1.5
#: The same budget in silhouette IoU (:data:`PLAN_GAP_DB`'s sentence holds for it).
PLAN_GAP_IOU = 0.02

#: The classic card's IoU gap with tables of three azimuths: the card shows its front view from every
#: side, so its IoU varies with the azimuth more than three samples average out (the ring morph's does
#: not); three times the planner's IoU budget.
PLAN_CARD_GAP_IOU = 0.06

#: The margin the planner keeps between a frame's predicted box PSNR and the budget
#: (:func:`morphkit.plan.planner.choose`): a choice must be predicted to beat the budget by this
#: much, so that a frame whose measure falls short of its prediction by the median gap still meets it;
#: the plan's figures along the path and a representation's measured on its calibration frames are
#: held by it too (:func:`morphkit.programs.planning.planown.less_margin`).
PLAN_MARGIN_DB = 0.5
#: The same margin in silhouette IoU (:data:`PLAN_MARGIN_DB`'s sentence holds for it).
PLAN_MARGIN_IOU = 0.01
#: How many times the planner chooses again when its plan, drawn on its own calibration frames, misses
#: the budget along the path (each time with the margins of the representations it drew widened by the
#: shortfall); then the representations everywhere measured to meet it on the calibration frames or
#: predicted to along the path by their margins, the cheapest first.
PLAN_RECHOICES = 2
#: How much faster than the plan a representation everywhere must be, both timed on the plan's own
#: calibration frames (interleaved, the medians of their draws), to be drawn as the plan instead (taken
#: where it meets the budget along the path too): a frame mixing representations pays each one's pass,
#: which the representations' cost lines, each measured everywhere, do not predict; 5 % is over the
#: noise between such medians on a shared machine, and a twentieth of the 1.10 a plan may cost over
#: the cheapest sweep that meets its budget.
PLAN_TIMED_FASTER = 1.05
#: The fewest billboards of a band measured in the calibration frames that give the band its own
#: offset (:func:`morphkit.plan.calibration.band_offsets`): the median of fewer is one billboard's luck.
PLAN_MIN_BAND_BILLBOARDS = 5
#: The most instances a plan predicts its frames from (:func:`morphkit.plan.planner.predict_frames`):
#: a larger scene is predicted from a random sample of this many, whose frames' mean figures estimate
#: the whole scene's (planning then takes the same time for 2 thousand instances as for 100 thousand).
PLAN_MAX_INSTANCES = 2000
#: How far a box's coverage fractions (:func:`morphkit.plan.framecoverage.union_iou`: covered by the
#: representation, the truth, both) may stray outside what silhouettes can cover: the rounding of
#: means over pixels and azimuths.
COVERAGE_FRACTION_ATOL = 1e-9
#: The shortest on-screen height (pixels) a plan's error tables measure: twice the scene's smallest
#: drawn billboard (``min_pixels``, 2), so a far field of tiny billboards is looked up where it is
#: measured, not at a larger one's row.
PLAN_MIN_TABLE_HEIGHT_PX = 4.0
#: The largest calibration offset a plan applies to the tables' predicted box PSNR (dB); a larger
#: one is held to it, and said: the tables then describe the scene's billboards poorly.
PLAN_MAX_OFFSET_DB = 6.0
#: The same bound on the IoU offset (:data:`PLAN_MAX_OFFSET_DB`'s sentence holds for it).
PLAN_MAX_OFFSET_IOU = 0.1
#: The tallest on-screen height (pixels) a plan's error tables measure: a billboard taller than
#: this fills most of a frame of up to 1080 rows, and its cell's frame grows with its square.
PLAN_MAX_TABLE_HEIGHT_PX = 1024.0

#: Largest side (pixels) of an atlas :mod:`morphkit.export` writes into a glTF file: WebGL 2 promises
#: only 2048 (``MAX_TEXTURE_SIZE``), and 4096 is what the devices in use give at least; a larger
#: atlas is refused (bake smaller views) rather than written for engines that cannot load it.
EXPORT_MAX_TEXTURE_SIDE = 4096

#: The largest side (pixels) of a plan's error-table cell frame (:func:`morphkit.plan.errortable.fit_frame`):
#: a quad flaring wider than it (an upright ring quad close under a high eye) is cut at the frame's
#: edges, as any frame a scene draws cuts it; 4096 holds every quad of the grid's tallest row,
#: :data:`PLAN_MAX_TABLE_HEIGHT_PX`, at eye level (its diagonal, for quads up to 3.9 times as wide
#: as high), and keeps a cell's frame (and its truth's render) at 16.8 M pixels.
PLAN_MAX_TABLE_FRAME_PX = 4096

#: The most instances of one asset a scene's GLB writes as nodes of their own, when the asset has
#: levels of detail (:func:`morphkit.export.assetglb.write_scene_glb`): ``MSFT_lod`` switches per node,
#: ``EXT_mesh_gpu_instancing`` draws all of a node's instances at one level, so each instance is a
#: node (its meshes shared) and its JSON grows with the instances (about 0.5 kB each).
EXPORT_MAX_LOD_INSTANCES = 10_000
