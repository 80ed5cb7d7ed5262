"""Scene output ``wav``: the auralize job built from a scene's one damper run.

:func:`wav_settings` turns ``[outputs.wav]`` and the scene's sound tables (the damper, the contact, the
cavity's surroundings, the listeners, the room's sound) into the
:class:`~acoustiviz.app.settings.auralize.AuralizeJob` that ``acoustiviz auralize`` builds from its
options; :func:`wav_products` turns its result into the summary's products. The cavity and the listeners
are those the scene's ``levels`` and ``spectrum`` hear (:func:`acoustiviz.app.scene_levels.damper_cavity`).
"""

from __future__ import annotations

from pathlib import Path

from ..core.listener import Listener
from .scene_levels import damper_cavity

__all__ = ["wav_settings", "wav_products"]


def wav_settings(scene, out=None, damper=None):
    """The scene's ``[outputs.wav]`` as an :class:`~acoustiviz.app.settings.auralize.AuralizeJob`.

    ``damper``: the scene's damper run's :class:`~acoustiviz.app.settings.damper_job.DamperJob` (without
    files); the WAV files are ``wav_NAME.wav`` per listener, or ``wav_stereo.wav``, in folder ``out`` (None:
    no files, the checks of the scene's settings alone, made before the run folder exists); errors name
    scene keys.
    """
    from ..sound import ClickModel
    from .settings.auralize import AuralizeJob

    opts, contact = scene.output_or_defaults("wav"), scene.section("contact")
    model, radius = damper.model, scene.damper_sphere_radius()
    click = ClickModel(k_hertz=model.k_hertz, mass=model.m, main_mass=model.M, mass_model=contact["pulse_mass"],
                       pulse=contact["pulse"])
    listeners = tuple(Listener(name, position) for name, position in scene.listeners(radius))
    if opts["stereo"]:
        listeners = listeners[:2]
    stems = ["wav_stereo"] if opts["stereo"] else [f"wav_{lst.name}" for lst in listeners]
    files = () if out is None else tuple(str(Path(out) / f"{stem}.wav") for stem in stems)
    names = AuralizeJob.names_for("scene")
    return AuralizeJob(model, damper_cavity(scene, model, scene.medium()), click, listeners, files, damper.duration,
                       damper, room_sound=scene.room_sound(), stereo=opts["stereo"], rate=opts["rate_hz"],
                       subtype=opts["subtype"], max_memory_mb=scene.section("grids")["memory_limit_mb"],
                       radius_source=f"scene: sphere.damper_radius = {scene.section('sphere')['damper_radius']!r}",
                       scene_name=scene.name, names=names)


def wav_products(result) -> list:
    """The summary's products of a written auralize result: each WAV file with its key figures, and its sidecar."""
    from .products import Product

    job, products = result.settings, []
    for wav, w in zip(job.wav_files, result.written, strict=True):
        rec = w["record"]
        lvl = max((v for v in rec["peak_spl_db_re_20upa"] if v is not None), default=float("nan"))
        phys = max((v for v in rec["physical_peak_spl_db_re_20upa"] if v is not None), default=float("nan"))
        counts = {k: str(v) for k, v in result.collisions.items()}  # several balls: ball-wall and ball-ball too
        products += [Product("wav", Path(wav), {**counts, "peak_spl_db": f"{lvl:.1f}",
                                                "physical_peak_spl_db": f"{phys:.1f}", "subtype": rec["subtype"],
                                                "rate_hz": str(job.rate)}),
                     Product("wav", Path(w["sidecar"]), {})]
    return products
