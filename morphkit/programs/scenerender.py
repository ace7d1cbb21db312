"""A scene drawn into a folder: ``morphkit render SCENE`` and ``morphkit billboards``.

:func:`render_scene` bakes (or reads) the scene's assets, places its instances, and draws its
camera path with view-morphed billboards (:func:`morphkit.programs.sequence.write_sequence`):
the frames, a video, comparison strips against the real meshes (with ray-cast shadows under
a sun) and a summary JSON. The ``billboards`` command is the scene its flags describe
(:func:`scene_from_flags`), drawn by the same function, so a scene it saves
(``--save-scene``) renders as the command did.

What is decided here, said in one line each on stdout: the views the assets need
(:func:`morphkit.programs.cliargs.choose_views`), instances moved apart, a sun taken for
shadows when the scene has none, the notes of a glTF scene.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..billboard import Backdrop, BillboardScene, Fog, MeshMode, MorphCache, MorphMode
from ..billboard.asset import BAKE_AMBIENT, bake_lights
from ..billboard.frames.facing import AxialFacing, ViewpointFacing
from ..billboard.frames.instances import Instances, footprint_radius
from ..errors import ValidationError, expected_got
from ..files.outfolder import RENDER_OUTPUT, OutputClaim, claim_output
from ..imaging.shading import Lighting
from ..render import Renderer
from ..scenes.camerapaths import NamedPath
from ..scenes.description import SOFT_PCSS, VIEWS_DOME, SceneAsset, SceneDescription, SceneShadows
from ..scenes.placing import Scatter
from ..scenes.suns import BakeLight, DaySun, FixedSun
from ..sunlit.litmesh import LitMeshMode
from ..sunlit.litmodes import ClassicSurface, LitMode, MorphSurface
from ..views.dome import ViewDome
from .cliargs import choose_views, parse_size
from .sceneshadows import SceneCasters, scene_shadows
from .sequence import write_sequence
from .sources import ResolvedAssets, asset_name, check_specs, resolve_assets

__all__ = [
    "render_scene",
    "scene_choices",
    "prepare_scene",
    "PreparedScene",
    "scene_cameras",
    "scene_specs",
    "scene_from_flags",
]


def scene_from_flags(args: argparse.Namespace) -> SceneDescription:
    """The scene the ``billboards`` options describe (checked by :mod:`morphkit.programs.cliargs`,
    sun options implied already): its assets, ``--n`` instances scattered from ``--seed`` and moved
    apart, the ``--path`` camera, the sun, the shadows and the image.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed ``billboards`` options.

    Returns
    -------
    SceneDescription

    Raises
    ------
    ValidationError
        A bad ``--size``, count or asset (refused before anything is baked or written).
    """
    shape = parse_size(args.size)
    for name, v, lo in (
        ("--n", args.n, 0),
        ("--frames", args.frames, 1),
        ("--asset-size", args.asset_size, 16),
    ):
        if v < lo:
            raise ValidationError(expected_got(name, f"an int >= {lo}", v))
    specs = args.asset or ["tree", "person"]
    check_specs(specs)
    assets = tuple(SceneAsset(asset_name(sp), sp, up=args.up_axis) for sp in specs)
    shadows = None
    if args.shadows:
        shadows = SceneShadows(
            args.soft if args.soft in (None, SOFT_PCSS) else int(args.soft),
            args.sun_atlas_size,
            args.sun_radius,
        )
    views = None if args.views is None else (VIEWS_DOME if args.views == VIEWS_DOME else int(args.views))
    return SceneDescription(
        assets,
        Scatter(args.n, args.seed),
        camera=NamedPath(args.path),
        sun=DaySun() if args.sun_path else BakeLight(),
        shape=shape,
        frames=args.frames,
        views=views,
        asset_size=args.asset_size,
        shadows=shadows,
        fog=not args.no_fog,
    )


def scene_specs(scene: SceneDescription) -> list[str]:
    """The sources of the scene's assets read from files or sample names (a glTF scene's meshes,
    held in memory, are not among them).

    Parameters
    ----------
    scene : SceneDescription

    Returns
    -------
    list of str
    """
    return [a.source for a in scene.assets if a.mesh is None]


def scene_cameras(scene: SceneDescription) -> list[Any]:
    """The scene's cameras, fitted to where its instances first stand.

    Parameters
    ----------
    scene : SceneDescription

    Returns
    -------
    list of CameraModel
    """
    first = scene.instances.first(scene.names) if scene.assets else None
    half = float(np.abs(first.xy).max()) if first is not None and len(first) else 1.0
    return scene.camera.cameras(scene.frames, scene.shape, max(half, 1.0))


def _resolve(
    scene: SceneDescription, renderer: Renderer, views: int | None, dome: ViewDome | None
) -> ResolvedAssets:
    """Each asset baked or read (:func:`~morphkit.programs.sources.resolve_assets`), under the
    scene's name for it; a glTF scene's meshes baked from memory."""
    from ..bake.manifest import ManifestRecords

    assets: dict[str, Any] = {}
    items: dict[str, list[Any]] = {}
    skipped: dict[str, str] = {}
    for a in scene.assets:
        if a.mesh is not None:
            res = resolve_assets(
                [],
                renderer,
                views=views or 8,
                size=scene.asset_size,
                dome=dome,
                meshes={a.name: a.mesh},
                progress=True,
            )
        else:
            res = resolve_assets(
                [a.source],
                renderer,
                views=views or 8,
                size=scene.asset_size,
                up=a.up,
                progress=True,
                dome=dome,
                records=ManifestRecords(),
            )
        ((got, asset),) = res.assets.items()
        asset.name = a.name
        assets[a.name] = asset
        if got in res.items:
            items[a.name] = res.items[got]
        else:
            skipped[a.name] = res.skipped.get(got, "no mesh")
    return ResolvedAssets(assets, items, skipped)


def _placed(scene: SceneDescription, res: ResolvedAssets, head: str, smaller: str) -> Instances:
    """The instances where the scene puts them, moved apart where it scatters them (each asset's
    footprint from its mesh where the run has it, else its quad's half width: a bound), at their
    asset's size; one line says how many moved, a warning how many overlap."""
    names = list(scene.names)
    size = {a.name: a.scale for a in scene.assets}
    radius = {
        nm: size[nm]
        * (footprint_radius(res.items[nm]) if nm in res.items else float(res.assets[nm].half_extent[0]))
        for nm in names
    }
    placed = scene.instances.place(names, radius)
    inst = placed.instances
    n = len(inst)
    if placed.moved:
        print(
            f"{head}{placed.moved} of {n} instances moved apart so that none stands inside another",
            flush=True,
        )
    if placed.overlapping:
        why = (
            f"the field is too small for {n} of these assets (give a smaller {smaller})"
            if isinstance(scene.instances, Scatter) and scene.instances.apart
            else "drawn where the scene puts them"
        )
        warnings.warn(f"{placed.overlapping} of {n} instances still overlap another: {why}", stacklevel=2)
    if any(s != 1.0 for s in size.values()):
        per = np.array([size[nm] for nm in inst.names], np.float64)
        inst = dataclasses.replace(inst, scale=inst.scale * per[inst.asset] if n else inst.scale)
    return inst


@dataclasses.dataclass(eq=False)
class PreparedScene:
    """A scene made ready to draw (:func:`prepare_scene`): its billboard scene, its lights and
    shadows, and the modes that draw it and its truth.

    Parameters
    ----------
    scene : BillboardScene
        The assets baked or read, the instances placed.
    resolved : ResolvedAssets
        What each asset came from (its mesh items where the run has them).
    relit : bool
        Relit dome assets (a sun), else ring assets under the bake's light.
    base : Lighting
        The bake's light and ambient (the relit modes' lighting before a frame sets the sun's).
    lighting : list of Lighting or None
        One per frame under a sun, else None.
    shadow, truth_shadow : SceneShadow or None
        The frames' shadow and the ray cast the truth is drawn with (None without shadows).
    truth : FrameMode or None
        The real meshes (None when an asset has no mesh).
    casters : SceneCasters or None, optional
        The shadows' casters (None without shadows): other shadows of the scene are made from them
        (:meth:`~morphkit.programs.sceneshadows.SceneCasters.shadow`).
    """

    scene: BillboardScene
    resolved: ResolvedAssets
    relit: bool
    base: Lighting
    lighting: list[Lighting] | None
    shadow: Any
    truth_shadow: Any
    truth: Any
    casters: SceneCasters | None = None

    def mode(self, choice: Any = None) -> Any:
        """The mode drawing the scene: relit billboards of ``choice`` (default the dome's morph,
        :class:`~morphkit.sunlit.litmodes.MorphSurface`) with the scene's shadow, or ring
        billboards view-morphed (``choice`` must be None).

        Parameters
        ----------
        choice : SurfaceChoice, optional
            The relit billboards' surface.

        Returns
        -------
        FrameMode
        """
        if self.relit:
            return LitMode(MorphSurface() if choice is None else choice, self.base, shadow=self.shadow)
        if choice is not None:
            raise ValidationError(
                expected_got(
                    "choice", "None for ring assets (a SurfaceChoice is relit)", type(choice).__name__
                )
            )
        return MorphMode(MorphCache())

    def meshes(self) -> Any:
        """A mode drawing the real meshes as the truth does, without its ray-cast shadow (a plan's
        bands of the real mesh take the frame's: :mod:`morphkit.plan.mixed`); None without meshes.

        Returns
        -------
        LitMeshMode, MeshMode or None
        """
        if self.truth is None:
            return None
        return dataclasses.replace(self.truth, shadow=None) if self.relit else dataclasses.replace(self.truth)

    def classic(self) -> Any:
        """The classic billboards of the comparisons (None: the ring's own classic mode).

        Returns
        -------
        FrameMode or None
        """
        return LitMode(ClassicSurface(), self.base, shadow=self.shadow) if self.relit else None


def prepare_scene(
    scene: SceneDescription,
    renderer: Renderer,
    views: int | None,
    *,
    head: str = "morphkit render: ",
    command: str = "render",
    smaller: str = "scatter count",
    sun: Any = None,
    shadows: SceneShadows | None = None,
) -> PreparedScene:
    """Bake (or read) ``scene``'s assets, place its instances, set up its lights, shadows and
    truth (what :func:`render_scene` draws; :mod:`morphkit.programs.planning.planrun` plans).

    Parameters
    ----------
    scene : SceneDescription
        With at least one asset.
    renderer : Renderer
        Bakes the assets and draws the truth.
    views : int or None
        Views per ring (None: dome assets, :func:`~morphkit.programs.cliargs.choose_views`).
    head : str, optional
        The start of each line printed.
    command : str, optional
        The command's name (``billboards`` names its flags in errors).
    smaller : str, optional
        What to make smaller when a scatter cannot hold its instances apart.
    sun : SceneSun, optional
        The sun drawn with (default the scene's).
    shadows : SceneShadows, optional
        How the frames' shadow is drawn, when not as the scene says (a plan's choice,
        :mod:`morphkit.plan.shadowchoice`): its atlases' size and softness; the truth keeps the
        scene's (and the scene's sun disc is kept).

    Returns
    -------
    PreparedScene

    Raises
    ------
    ValidationError
        Shadows of an asset without a mesh.
    """
    sun = scene.sun if sun is None else sun
    dome = ViewDome() if views is None else None
    res = _resolve(scene, renderer, views, dome)
    names = list(scene.names)
    inst = _placed(scene, res, head, smaller)
    fog = Fog() if scene.fog else None
    facing = ViewpointFacing() if dome is not None else AxialFacing()
    bscene = BillboardScene(res.assets, inst, backdrop=Backdrop(ground=scene.ground, fog=fog), facing=facing)
    base = Lighting(BAKE_AMBIENT, tuple(bake_lights()))
    suns = sun.suns(scene.frames)
    lighting = None if suns is None else [Lighting(BAKE_AMBIENT, (s,)) for s in suns]
    known = all(nm in res.items for nm in names)
    if not known:
        why = "; ".join(f"{nm}: {res.skipped.get(nm, 'no mesh')}" for nm in names if nm not in res.items)
        print(f"{head}comparisons with the real meshes skipped: {why}", file=sys.stderr)
    shadow = truth_shadow = truth = casters = None
    if scene.shadows is not None:
        shadow, truth_shadow, casters = scene_shadows(
            scene.shadows,
            res,
            renderer,
            names,
            [a.source for a in scene.assets],
            head,
            "--shadows" if command == "billboards" else "shadows",
        )
        if shadows is not None and shadows != scene.shadows:
            shadow = casters.shadow(dataclasses.replace(shadows, sun_radius_deg=scene.shadows.sun_radius_deg),
                                    renderer)
    if known:
        truth = (
            LitMeshMode(renderer, res.items, base, shadow=truth_shadow)
            if dome is not None
            else MeshMode(renderer, res.items, bake_lights(), BAKE_AMBIENT)
        )
    return PreparedScene(bscene, res, dome is not None, base, lighting, shadow, truth_shadow, truth, casters)


def _asset_entry(a: SceneAsset, inst: Instances) -> dict[str, Any]:
    k = inst.names.index(a.name) if a.name in inst.names else -1
    return {
        "name": a.name,
        "source": a.source,
        "instances": int(np.count_nonzero(inst.asset == k)),
        "scale": a.scale,
    }


def scene_choices(
    scene: SceneDescription, command: str = "render", path_label: str | None = None
) -> tuple[Any, int | None, list[Any], str, str]:
    """What drawing ``scene`` decides before any work, its notes printed and the lines of its
    choices made: the sun (a day's when shadows have none), the views
    (:func:`~morphkit.programs.cliargs.choose_views`), the cameras and the path's label.

    Parameters
    ----------
    scene : SceneDescription
        The scene.
    command : str, optional
        The command's name, at the start of each line printed.
    path_label : str, optional
        The camera path's name (default: the scene camera's).

    Returns
    -------
    sun : SceneSun
    views : int or None
        Views per ring, None for dome assets.
    cameras : list of CameraModel
    label : str
    chosen : str
        The line saying how the views were chosen ("" when the scene said).

    Raises
    ------
    ValidationError
        A scene without assets.
    """
    head = f"morphkit {command}: "
    for note in scene.notes:  # what reading the file ignored or chose (a glTF without meshes says so)
        print(head + note, flush=True)
    if not scene.assets:
        raise ValidationError(expected_got("scene", "at least one asset", "none"))
    sun = scene.sun
    if scene.shadows is not None and isinstance(sun, BakeLight):
        sun = DaySun()
        print(
            head + "shadows take the default sun (a day's, as --sun-path day): the scene has none", flush=True
        )
    relit = not isinstance(sun, BakeLight)
    cams = scene_cameras(scene)
    label = path_label or scene.camera.to_json().get("path", "keyframes")
    views, chosen = choose_views(
        scene.views,
        ("--sun-path" if command == "billboards" else "the scene's sun") if relit else None,
        label,
        cams,
        scene_specs(scene),
        head,
    )
    return sun, views, cams, label, chosen


def render_scene(
    scene: SceneDescription,
    out: OutputClaim | str | os.PathLike[str],
    *,
    overwrite: bool = False,
    command: str = "render",
    stem: str = "render",
    path_label: str | None = None,
    said: Sequence[str] = (),
    smaller: str = "scatter count",
    compare: int | None = 3,
    mode: Any = None,
    plan: dict[str, Any] | None = None,
    shadows: SceneShadows | None = None,
) -> dict[str, Any]:
    """Draw ``scene`` into the folder ``out`` (the module notes).

    Parameters
    ----------
    scene : SceneDescription
        With at least one asset.
    out : OutputClaim or path-like
        The output folder: a path (checked here as ``morphkit render``'s, before any work), or one
        checked by the command already (:func:`morphkit.files.outfolder.claim_output`); written
        once the scene's choices are checked.
    overwrite : bool, optional
        Replace a previous ``render`` run in a folder given as a path.
    command : str, optional
        The command's name, at the start of each line it prints.
    stem : str, optional
        The video's and the summary's name (:func:`~morphkit.programs.sequence.write_sequence`).
    path_label : str, optional
        The camera path's name in the lines printed (default: the scene camera's).
    said : sequence of str, optional
        Lines the command prints first (what its flags implied).
    smaller : str, optional
        What to make smaller when a scatter cannot hold its instances apart (the option's name).
    compare : int or None, optional
        How many frames (spread over the camera path) are also drawn with the real meshes and
        measured against them (``compare_NNNN.png``, their errors in the summary); None: every frame.
    mode : callable, optional
        Makes the frames' mode from the :class:`PreparedScene` (``render --plan``: the plan's
        mode); default :meth:`PreparedScene.mode`.
    plan : dict, optional
        What the summary says of the plan drawn (its ``"plan"`` entry).
    shadows : SceneShadows, optional
        How the frames' shadow is drawn when not as the scene says (a plan's shadow; the truth keeps
        the scene's: :func:`prepare_scene`).

    Returns
    -------
    dict
        The summary written to ``out/STEM.json``, with ``"assets"``: one entry per asset (its
        name, source, instance count and scale) and ``"notes"``.

    Raises
    ------
    ValidationError
        A scene without assets, or shadows of an asset without a mesh.
    OutputExistsError
        A folder given as a path holding another command's files, or a previous run without
        ``overwrite``.

    Examples
    --------
    The example fly-over, small and short (``morphkit render samples/scenes/flyover.json -o OUT``
    draws it whole)::

        import dataclasses
        import morphkit

        scene = morphkit.load_scene("samples/scenes/flyover.json")
        summary = morphkit.render_scene(dataclasses.replace(scene, frames=2, shape=(120, 160)), "out")
        print(summary["assets"], summary["compared"][0]["errors"])
    """
    claim = out if isinstance(out, OutputClaim) else claim_output(out, RENDER_OUTPUT, overwrite=overwrite)
    head = f"morphkit {command}: "
    sun, views, cams, label, chosen = scene_choices(scene, command, path_label)
    if said:
        print(head + "; ".join(said), flush=True)
    if chosen:
        print(chosen, flush=True)
    with claim.writing() as out, Renderer() as r:
        prep = prepare_scene(
            scene, r, views, head=head, command=command, smaller=smaller, sun=sun, shadows=shadows
        )
        inst = prep.scene.instances
        extra = (
            None
            if stem == "billboards"
            else {"assets": [_asset_entry(a, inst) for a in scene.assets], "notes": list(scene.notes)}
        )
        summary = write_sequence(
            prep.scene,
            cams,
            out,
            mode=prep.mode() if mode is None else mode(prep),
            truth=prep.truth,
            classic=prep.classic(),
            lighting=prep.lighting,
            progress=scene.frames >= 10,
            stem=stem,
            extra=extra if plan is None else {**(extra or {}), "plan": plan},
            compare=scene.frames if compare is None else compare,
        )
        names = list(scene.names)
    shadows = scene.shadows if shadows is None or scene.shadows is None else shadows
    kind = "relit dome assets" if prep.relit else "ring assets"
    if shadows is not None:
        kind += (
            ", shadows from sun atlases (the disc filtered from one map)"
            if shadows.soft == SOFT_PCSS
            else f", shadows from sun atlases ({shadows.soft or 1} sun direction(s))"
        )
    sun_label = "day" if isinstance(sun, DaySun) else "fixed" if isinstance(sun, FixedSun) else ""
    print(
        f"{head}{len(inst)} billboards of {', '.join(names)}, {scene.frames} frames "
        f"({label}{', sun: ' + sun_label if sun_label else ''}; {kind}), "
        f"cache hit rate {summary['hit_rate']:.1%}"
    )
    for c in summary["compared"]:
        errs = "; ".join(
            f"{m} IoU {e['iou']:.3f} PSNR {e['psnr']:.1f} dB" for m, e in c["errors"].items() if e["n"]
        )
        print(f"  {c['file']}: classic | morph | mesh; per billboard vs mesh: {errs}")
    print(f"wrote {len(summary['files'])} files to {out.resolve()}")
    return summary
