"""A room's WAV with the statistical late tail and absorption per octave band (``RoomSound``).

References, independent of the code under test: Eyring's reverberation time (closed form,
:func:`acoustiviz.core.reverberation.reverberation_time`, checked in ``test_reverberation.py``)
against the Schroeder backward integral of the rendered response; the exact render (every image
in closed form through the fractional-delay trains) for the early part and the tail's onset
level; the single-alpha room for a banded room whose bands are all equal.
"""

import json
import math

import numpy as np
import pytest

from acoustiviz.app.wav import cavity
from acoustiviz.cli import main
from acoustiviz.core.reverberation import reverberation_time
from acoustiviz.core.room import Shoebox
from acoustiviz.errors import ParameterError, SceneError
from acoustiviz.scene.load import scene_from_text
from acoustiviz.sound import ClickModel, ImpactSequence, RoomSound, parse_absorption_bands, render

A = 0.01905
DIMS = (6.0, 4.0, 3.0)
SOURCE = (2.0, 1.5, A)
LISTENER = [3.0, 2.0, 1.5]
FS = 48000
ONE = ImpactSequence([0.001], [-1], [1.4])  # one click: the room's response to it


def _room(alpha=0.1, source=SOURCE, **kw):
    return cavity("free", A, 0.04, room={"dimensions": DIMS, "absorption": alpha, "source": source, **kw})


def _schroeder_t30(p, fs, lo_db=-5.0, hi_db=-35.0):
    """T60 from the -5 to -35 dB slope of the backward-integrated energy (Schroeder 1965, ISO 3382)."""
    e = np.cumsum((p**2)[::-1])[::-1]
    db = 10 * np.log10(e / e[0])
    i0, i1 = np.argmax(db <= lo_db), np.argmax(db <= hi_db)
    t = np.arange(p.size) / fs
    slope = np.polyfit(t[i0:i1], db[i0:i1], 1)[0]
    return -60.0 / slope


# ------------------------------------------------------------------------------- the tail
def test_early_part_is_the_exact_render():
    """Before the transition the tail's render is the exact one: the direct click to round-off, the
    reflections to the fractional-delay interpolator's accuracy (about 1e-5 of the peak)."""
    raised = (2.0, 1.5, 1.0)  # the sphere above the floor: the direct click arrives alone
    exact = render(ONE, _room(0.3, raised, duration=0.08), ClickModel(), LISTENER, sample_rate=FS)
    tail = render(ONE, _room(0.3, raised, duration=0.08), ClickModel(), LISTENER, sample_rate=FS,
                  room_sound=RoomSound(late_tail=True))
    t_x = tail.room["transition_s"]
    assert tail.room["late_tail"] and 0.008 < t_x < 0.05
    p, q = exact.pressure[0], tail.pressure[0]
    peak = np.abs(p).max()
    r0 = np.linalg.norm(np.subtract(LISTENER, raised))
    first_reflection = 0.001 + (np.linalg.norm(np.subtract(LISTENER, (2.0, 1.5, -1.0))) - A) / 343.2
    # before the floor image's click with its pre-ringing: the fractional delay's 48 samples and the
    # decimation filter's half-length (74 samples at 864 kHz internal rate): 2.7 ms
    guard = (48 + 80) / FS
    direct = slice(0, int((first_reflection - guard) * FS))
    assert 0.001 + (r0 - A) / 343.2 + 0.001 < first_reflection - guard
    np.testing.assert_allclose(q[direct], p[direct], rtol=0, atol=1e-12 * peak)
    early = slice(0, int((0.001 + t_x) * FS) - 48)  # up to the sinc half-length before the cut
    # each reflection's click is delayed by the same windowed-sinc interpolator, at a fractional delay
    # counted from the impact (exact render) or from the direct sound (here): 1e-5 of the peak apart
    np.testing.assert_allclose(q[early], p[early], rtol=0, atol=5e-5 * peak)
    assert np.abs(q[early] - p[early]).max() > 0  # the two paths do differ (not the same code)


def test_tail_onset_level_is_the_exact_image_sum_energy():
    """Just after the transition the tail carries the energy of the images it replaces.

    Energy over 20 ms from the transition at three listeners, tail against the exact image sum
    (every image arriving in the window): the images' own energy fluctuates about 10 % per
    window with a few hundred of them, the noise's about as much, so each ratio within 2.5 dB
    and their mean within 1.2 dB.
    """
    ratios = []
    for listener in ([3.0, 2.0, 1.5], [4.6, 0.7, 2.2], [1.1, 3.2, 0.9]):
        exact = render(ONE, _room(0.1, duration=0.1), ClickModel(), listener, sample_rate=FS)
        tail = render(ONE, _room(0.1, duration=0.1), ClickModel(), listener, sample_rate=FS,
                      room_sound=RoomSound(late_tail=True))
        t_x = tail.room["transition_s"]
        w = slice(int((0.001 + t_x) * FS) + 48, int((0.001 + t_x + 0.02) * FS))
        ratios.append(np.sum(tail.pressure[0, w] ** 2) / np.sum(exact.pressure[0, w] ** 2))
    db = 10 * np.log10(ratios)
    assert np.all(np.abs(db) < 2.5), db
    assert abs(np.mean(db)) < 1.2, db


@pytest.mark.slow
def test_tail_decays_at_eyrings_reverberation_time():
    """Schroeder decay of the rendered response to one click: T30 within 10 % of Eyring's T60."""
    out = render(ONE, _room(0.1), ClickModel(), LISTENER, sample_rate=FS, room_sound=RoomSound(late_tail=True))
    te = reverberation_time(Shoebox(DIMS, 0.1), "eyring")
    t30 = _schroeder_t30(out.pressure[0], FS)
    assert abs(t30 / te - 1) < 0.10, (t30, te)
    assert out.room["tail_end_s"] > 0.9 * te  # the tail runs until -60 dB of the energy
    assert out.room["neglected_energy_db"] <= -60.0 + 0.5


def test_tail_is_reproducible_and_seeded():
    kw = dict(sample_rate=FS)
    a = render(ONE, _room(0.3), ClickModel(), LISTENER, room_sound=RoomSound(late_tail=True), **kw)
    b = render(ONE, _room(0.3), ClickModel(), LISTENER, room_sound=RoomSound(late_tail=True), **kw)
    c = render(ONE, _room(0.3), ClickModel(), LISTENER, room_sound=RoomSound(late_tail=True, seed=7), **kw)
    np.testing.assert_array_equal(a.pressure, b.pressure)
    n_x = int((0.001 + a.room["transition_s"]) * FS)
    guard = 128  # the click's decimation filter rings 74 samples ahead of the tail's onset
    np.testing.assert_array_equal(a.pressure[0, :n_x - guard], c.pressure[0, :n_x - guard])  # only the tail moves
    assert np.abs(a.pressure[0, n_x + 100:] - c.pressure[0, n_x + 100:]).max() > 0.1 * np.abs(a.pressure[0, n_x:]).max()


def test_without_room_sound_the_render_is_unchanged():
    """``room_sound=None`` is the exact render: the same samples bit for bit."""
    a = render(ONE, _room(0.3, duration=0.05), ClickModel(), LISTENER, sample_rate=FS)
    b = render(ONE, _room(0.3, duration=0.05), ClickModel(), LISTENER, sample_rate=FS, room_sound=None)
    np.testing.assert_array_equal(a.pressure, b.pressure)
    assert a.room is None and "room_sound" not in a.describe()


# ------------------------------------------------------------------------------- octave bands
BANDS = "250:0.2,500:0.2,1000:0.2,2000:0.2,4000:0.2"


def test_equal_bands_are_the_single_alpha_room():
    centres, alpha = parse_absorption_bands(BANDS)
    one = render(ONE, _room(0.2), ClickModel(), LISTENER, sample_rate=FS, room_sound=RoomSound(late_tail=True))
    banded = render(ONE, _room(0.2), ClickModel(), LISTENER, sample_rate=FS,
                    room_sound=RoomSound(late_tail=True, band_centres=centres, band_absorption=alpha))
    peak = np.abs(one.pressure).max()
    np.testing.assert_allclose(banded.pressure, one.pressure, rtol=0, atol=1e-9 * peak)
    # without the tail too: every image to the tolerance, per band
    one = render(ONE, _room(0.5), ClickModel(), LISTENER, sample_rate=FS, room_sound=RoomSound())
    c5, a5 = parse_absorption_bands("500:0.5,2000:0.5")
    banded = render(ONE, _room(0.5), ClickModel(), LISTENER, sample_rate=FS,
                    room_sound=RoomSound(band_centres=c5, band_absorption=a5))
    np.testing.assert_allclose(banded.pressure, one.pressure, rtol=0, atol=1e-9 * np.abs(one.pressure).max())


@pytest.mark.slow
def test_more_absorbing_band_decays_faster_at_its_eyring_time():
    """Two bands, alpha 0.1 below 1 kHz and 0.3 above: each band's Schroeder T30 within 10 % of its Eyring T60."""
    centres, alpha = parse_absorption_bands("500:0.1,2000:0.3")
    out = render(ONE, _room(0.1), ClickModel(), LISTENER, sample_rate=FS,
                 room_sound=RoomSound(late_tail=True, band_centres=centres, band_absorption=alpha))
    te = reverberation_time(Shoebox(DIMS, alpha), "eyring")
    p = np.concatenate([out.pressure[0], np.zeros(out.n_samples)])  # no circular wrap of the analysis filters
    f = np.fft.rfftfreq(p.size, 1 / FS)
    # analysis bands clear of the synthesis crossover (841 to 1189 Hz), with smooth edges (short ringing)
    low = np.clip((np.log2(841.0) - np.log2(np.maximum(f, 1.0))) / 0.25, 0, 1)
    high = np.clip((np.log2(np.maximum(f, 1.0)) - np.log2(1189.0)) / 0.25, 0, 1)
    spec = np.fft.rfft(p)
    t30 = [_schroeder_t30(np.fft.irfft(spec * np.sin(0.5 * np.pi * m) ** 2, p.size), FS) for m in (low, high)]
    assert te[0] > 1.5 * te[1]
    for got, want in zip(t30, te, strict=True):
        assert abs(got / want - 1) < 0.10, (t30, te)


# ------------------------------------------------------------------------------- command line and scene
ROOM = ["--room", "6,4,3", "--source", "2,1.5,0.01905", "--listener", "3,2,1.5", "--duration", "0.3"]


def test_cli_writes_the_tail_into_the_sidecar(tmp_path, capsys):
    wav = tmp_path / "o.wav"
    assert main(["auralize", *ROOM, "--absorption", "0.1", "--late-tail", "--wav", str(wav)]) == 0
    side = json.loads((tmp_path / "o.json").read_text())
    assert side["late_tail"] is True and side["image_order"] == side["room_sound"]["image_order"]
    assert side["images"] == (4 * side["image_order"] ** 3 + 6 * side["image_order"] ** 2 + 8 * side["image_order"]
                              + 3) // 3
    assert 0 < side["transition_s"] < 0.1 and side["neglected_energy_db"] <= -59.5
    assert side["room_sound"]["tail_seed"] == 20261126
    assert "late tail from" in capsys.readouterr().out


def test_cli_levels_hear_the_same_room(tmp_path):
    """--levels renders at 96 kHz with the same tail: the reverberant SEL well above the direct sound's.

    Diffuse-field estimate: reverberant over direct energy ``16 pi r^2 / A`` with
    ``A = -S ln(1 - alpha)``, about 15 (12 dB) at 1.86 m in this room; the dipole's direct sound
    towards the listener and the images' ``<cos^2> = 1/3`` move it by a few dB, so above 6 dB.
    """
    assert main(["auralize", *ROOM, "--absorption", "0.1", "--late-tail", "--levels",
                 "--wav", str(tmp_path / "t.wav")]) == 0
    assert main(["auralize", *ROOM, "--absorption", "0.9", "--image-order", "0", "--levels",
                 "--wav", str(tmp_path / "d.wav")]) == 0
    sel = [json.loads((tmp_path / f"{n}.json").read_text())["levels"]["channels"][0]["sel_db"] for n in "td"]
    assert sel[0] > sel[1] + 6.0, sel


def test_cli_and_scene_give_the_same_wav_bytes(tmp_path):
    bands = "125:0.1,250:0.15,500:0.2,1000:0.25,2000:0.3,4000:0.35"
    assert main(["auralize", *ROOM, "--late-tail", "--absorption-bands", bands, "--tail-seed", "3",
                 "--wav", str(tmp_path / "c.wav")]) == 0
    scene = tmp_path / "s.toml"
    scene.write_text(f"""
[scene]
name = "s"
[geometry]
kind = "room"
room_m = [6.0, 4.0, 3.0]
source_m = [2.0, 1.5, 0.01905]
[damper]
duration_s = 0.3
[[listeners]]
name = "l"
position_m = [3.0, 2.0, 1.5]
[outputs.wav]
late_tail = true
tail_seed = 3
absorption_bands = "{bands}"
""")
    assert main(["run", str(scene), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    assert (tmp_path / "c.wav").read_bytes() == (tmp_path / "out" / "wav_l.wav").read_bytes()
    side = json.loads((tmp_path / "out" / "wav_l.json").read_text())
    assert side["room_sound"]["absorption_bands_hz"] == [125.0, 250.0, 500.0, 1000.0, 2000.0, 4000.0]


@pytest.mark.parametrize("extra, option", [
    (["--late-tail"], "--late-tail"),  # without --room
    (["--room", "6,4,3", "--absorption", "0.1", "--tail-seed", "3"], "--tail-seed"),  # without --late-tail
    (["--room", "6,4,3", "--absorption", "0.1", "--late-tail", "--tail-seed", "-1"], "--tail-seed"),
    (["--room", "6,4,3", "--absorption", "0.1", "--late-tail", "--transition", "0"], "--transition"),
    (["--room", "6,4,3", "--absorption-bands", "125:0.1,250:1.0"], "--absorption-bands"),
    (["--room", "6,4,3", "--absorption-bands", "250:0.1,125:0.2"], "--absorption-bands"),
    (["--room", "6,4,3", "--absorption-bands", "125=0.1"], "--absorption-bands"),
    (["--room", "6,4,3", "--absorption-bands", "125:0.1/0.2"], "--absorption-bands"),
    (["--room", "6,4,3", "--absorption-bands", "5:0.1"], "--absorption-bands"),
    (["--room", "6,4,3", "--absorption", "0.1", "--absorption-bands", "125:0.1"], "--absorption-bands"),
    (["--room", "6,4,3", "--late-tail"], "--late-tail"),  # rigid: no decay
    (["--room", "6,4,3", "--absorption", "0.1", "--late-tail", "--image-order", "2"], "--image-order"),
    (["--room", "6,4,3", "--late-tail", "--absorption-bands", "125:0,250:0.2"], "--late-tail"),
])
def test_bad_room_sound_options_exit_2_naming_the_option(extra, option, tmp_path, capsys):
    args = ["auralize", *extra, "--listener", "3,2,1.5", "--wav", str(tmp_path / "o.wav")]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert option in err and len(err.splitlines()) == 1, err
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("room, wav, key", [
    (False, 'late_tail = true', "outputs.wav.late_tail"),  # the plane, not a room
    (True, 'absorption_bands = "125:2"', "outputs.wav.absorption_bands"),
    (True, 'absorption_bands = "125:0.1"\ntail_seed = -3', "outputs.wav.tail_seed"),
    (True, 'late_tail = true\nabsorption_bands = "125:0,250:0"', "outputs.wav.late_tail"),
])
def test_bad_scene_keys_name_the_key(room, wav, key):
    text = ("[geometry]\nkind = \"room\"\nroom_m = [6.0, 4.0, 3.0]\nwindow_s = 0.5\n" if room else "") + \
        "[[listeners]]\nname = \"l\"\nposition_m = [3.0, 2.0, 1.5]\n[outputs.wav]\n" + wav + "\n"
    with pytest.raises(SceneError) as err:
        scene_from_text(text)
    assert key in str(err.value)


@pytest.mark.parametrize("make, name", [
    (lambda: RoomSound(seed=-1), "seed"),
    (lambda: RoomSound(decay="sabine"), "decay"),
    (lambda: RoomSound(band_centres=(125.0,)), "band_absorption"),
    (lambda: RoomSound(band_centres=(125.0, 250.0), band_absorption=(0.1,)), "band_absorption"),
    (lambda: RoomSound(max_images=0), "max_images"),
    (lambda: render(ONE, cavity("plane", A, 0.04), ClickModel(), LISTENER, room_sound=RoomSound()), "room_sound"),
])
def test_bad_room_sound_arguments_name_the_parameter(make, name):
    with pytest.raises(ParameterError) as err:
        make()
    assert err.value.name == name


def test_band_syntax():
    c, a = parse_absorption_bands("125:0.1/0.1/0.1/0.1/0.1/0.1, 250:0.1/0.2/0.3/0.4/0.5/0.6")
    assert c.tolist() == [125.0, 250.0] and a.shape == (6, 2)
    assert a[:, 1].tolist() == [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
    c, a = parse_absorption_bands("1000:0.25")
    assert a.shape == (6, 1) and math.isclose(a[0, 0], 0.25)
