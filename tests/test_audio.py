"""Auralisation: band-limiting against finer computations, levels against the field evaluator,
the two walls against direct radiation sums, calibrated files read back independently."""

import json
import math
import shutil
import subprocess
import warnings

import numpy as np
import pytest
import soundfile as sf

from acoustiviz import sound
from acoustiviz.core.geometry import images_plane, images_wall_floor
from acoustiviz.core.images import ImageSource
from acoustiviz.core.medium import AIR
from acoustiviz.core.radiation import sphere_pressure
from acoustiviz.core.signal import Signal
from acoustiviz.errors import ParameterError
from acoustiviz.output import audio
from acoustiviz.sound import CavityScene, ClickModel, ImpactSequence, render

try:  # the field evaluator is the reference for levels; a plain radiation sum if it is absent
    from acoustiviz import field
except ImportError:  # pragma: no cover
    field = None

A = 0.01905  # the paper's sphere radius, m
M = 0.0405  # Table 1 impact mass, kg
LISTENER = np.array([0.495, 0.0, 0.514])  # 0.7 m at 45 degrees from the sphere's centre


def _direct(pulse, t, point, sources, radius, medium=AIR):
    """Reference: a plain sum of free-field spheres from the radiation core."""
    return sum(sphere_pressure(pulse, t, point[None, :], radius=radius, centre=s.position, axis=s.axis,
                               medium=medium)[0] for s in sources)


def _reference(pulse, t, point, cfg):
    if field is not None:
        return field.time_series(pulse, t, point[None, :], cfg)[0]
    return _direct(pulse, t, point, cfg.sources, cfg.radius)  # pragma: no cover


# --------------------------------------------------------------------------- band-limiting
def _bead():
    """A 3 mm steel bead on steel: 21 us contact, l = c/a = 114 000 1/s -- energy far above 24 kHz."""
    a = 0.003
    mass = 7800.0 * 4.0 / 3.0 * math.pi * a**3
    k = 4.0 / 3.0 * math.sqrt(a) * 1.15e11
    return CavityScene("plane", radius=a, gap=0.01), ClickModel(k_hertz=k, mass=mass)


def test_spectrum_below_nyquist_matches_a_much_finer_computation():
    fs, t_len = 48000, 0.01
    scene, model = _bead()
    point = np.array([0.3, 0.1, 0.25])
    times = [0.001234567, 0.0041111111, 0.0072345678]  # arbitrary sub-sample times
    walls, speeds = [-1, 1, -1], [1.3, 0.7, 0.21]
    out = render(ImpactSequence(times, walls, speeds), scene, model, point, sample_rate=fs, duration=t_len)
    y = out.pressure[0, : int(t_len * fs)]
    # reference: the exact pressure sampled 256 times finer (12.3 MHz), no filter at all
    fine = 256 * fs
    tf = np.arange(int(t_len * fine)) / fine
    ref = np.zeros_like(tf)
    for tk, w, u in zip(times, walls, speeds, strict=True):
        ref += _direct(model.pulse_for(u), tf - tk, point, sound.wall_sources(scene, w), scene.radius)
    assert abs(ref[-1]) < 1e-9 * np.abs(ref).max()  # every click has died out inside the window
    spec_ref = np.fft.rfft(ref)[: y.size // 2 + 1] / 256  # the same bins k / t_len
    spec = np.fft.rfft(y)
    f = np.fft.rfftfreq(y.size, 1 / fs)
    band = f <= sound.PASSBAND_FRACTION * fs
    err = np.max(np.abs(spec[band] - spec_ref[band])) / np.max(np.abs(spec_ref))
    # the filter's passband ripple is 3e-6; the fine reference's own aliasing is ~1e-5
    assert err < 1e-4, err
    # ... whereas sampling the same clicks directly at 48 kHz aliases: the test can tell
    naive = ref[::256]
    err_naive = np.max(np.abs(np.fft.rfft(naive)[band] - spec_ref[band])) / np.max(np.abs(spec_ref))
    assert err_naive > 100 * err
    # above the passband the output only falls: at most its reference level plus the 3e-6 ripple
    trans = ~band
    assert np.all(np.abs(spec[trans]) <= np.abs(spec_ref[trans]) * (1 + 1e-5) + 1e-4 * np.abs(spec_ref).max())


def test_filter_meets_its_specification():
    from scipy.signal import freqz

    for L in (16, 37):
        h = sound.decimation_filter(L)
        assert h.size % (2 * L) == 1 and np.allclose(h, h[::-1])
        f, H = freqz(h, worN=2**16, fs=L)  # frequency in units of the output rate
        assert np.max(np.abs(np.abs(H[f <= sound.PASSBAND_FRACTION]) - 1)) < 1e-5
        assert 20 * np.log10(np.max(np.abs(H[f >= 0.5]))) < -sound.STOPBAND_ATTENUATION_DB


@pytest.mark.parametrize("frac", [0.0, 0.37, 0.91])
def test_sub_sample_placement_is_a_pure_delay(frac):
    """A click delayed by a fraction of a sample equals the first one shifted in the frequency domain."""
    fs = 48000
    scene, model = CavityScene("plane", radius=A), ClickModel(mass=M)
    t0, n = 0.002, 1024
    y0 = render(ImpactSequence([t0], [-1], [1.4]), scene, model, LISTENER, sample_rate=fs, duration=n / fs)
    y1 = render(ImpactSequence([t0 + (5 + frac) / fs], [-1], [1.4]), scene, model, LISTENER, sample_rate=fs,
                duration=n / fs)
    a0, a1 = y0.pressure[0, :n], y1.pressure[0, :n]
    f = np.fft.rfftfreq(n, 1 / fs)
    shifted = np.fft.irfft(np.fft.rfft(a0) * np.exp(-2j * np.pi * f * (5 + frac) / fs), n)
    assert np.max(np.abs(a1 - shifted)) < 1e-5 * np.max(np.abs(a0))


# --------------------------------------------------------------------------- levels
def test_one_click_peak_and_rms_match_the_field_evaluator():
    """At 96 kHz one click keeps its peak to 0.5 % and its energy (RMS over any window holding it) to 1e-4.

    The energy lost is what lies above the 43.2 kHz passband (< 1e-7 here); the peak moves because the
    samples fall up to half a sample (5.2 us) from the true maximum of a waveform whose time scale is
    a/c = 55 us, and because band-limiting rounds the corners of the waveform.
    """
    fs = 96000
    scene, model = CavityScene("plane", radius=A), ClickModel(mass=M)
    tk, window = 0.0123456789, 0.01
    out = render(ImpactSequence([tk], [-1], [1.4]), scene, model, LISTENER, sample_rate=fs, duration=0.03)
    pulse = model.pulse_for(1.4)
    tf = np.arange(0.0, window, 1 / (64 * fs))
    ref = _reference(pulse, tf, LISTENER, images_plane(A))
    y = out.pressure[0]
    assert np.max(np.abs(y)) == pytest.approx(np.max(np.abs(ref)), rel=5e-3)
    rms = math.sqrt(np.sum(y**2) / fs / window)
    rms_ref = math.sqrt(np.sum(ref**2) / (64 * fs) / window)
    assert rms == pytest.approx(rms_ref, rel=1e-4)
    assert out.peak_spl[0] == pytest.approx(20 * math.log10(np.max(np.abs(ref)) / 20e-6), abs=0.05)
    # and sample by sample against the reference band-limited by the filter's own frequency response
    n = 1024
    seg = y[int(tk * fs) - 100: int(tk * fs) - 100 + n]
    t_seg = (np.arange(n) + int(tk * fs) - 100) / fs - tk
    ff = 64
    tf2 = t_seg[0] + np.arange(n * ff) / (ff * fs)
    fine = _reference(pulse, tf2, LISTENER, images_plane(A))
    from scipy.signal import freqz

    L = round(out.internal_rate / fs)
    spec = np.fft.rfft(fine)
    freqs = np.fft.rfftfreq(fine.size, 1 / (ff * fs))
    _, H = freqz(sound.decimation_filter(L), worN=freqs, fs=L * fs)
    bl = np.fft.irfft(spec * np.abs(H), fine.size)[::ff]
    assert np.max(np.abs(seg - bl)) < 2e-4 * np.max(np.abs(bl))


def test_far_wall_radiates_reversed_from_the_far_wall():
    """Wall +1 (the far wall): sphere at a + gap on the axis, accelerating along -z, imaged in z = 0."""
    fs, gap = 96000, 0.04
    scene, model = CavityScene("plane", radius=A, gap=gap), ClickModel(mass=M)
    out = render(ImpactSequence([0.001], [1], [1.0]), scene, model, LISTENER, sample_rate=fs, duration=0.01)
    pulse = model.pulse_for(1.0)
    src = [ImageSource([0, 0, A + gap], [0, 0, -1]), ImageSource([0, 0, -A - gap], [0, 0, 1])]
    t = np.arange(0, 0.01, 1 / (32 * fs))
    ref = _direct(pulse, t - 0.001, LISTENER, src, A)
    assert out.peak[0] == pytest.approx(np.max(np.abs(ref)), rel=5e-3)
    e, e_ref = np.sum(out.pressure[0] ** 2) / fs, np.sum(ref**2) / (32 * fs)
    assert e == pytest.approx(e_ref, rel=1e-4)
    # the reversed axis flips the sign of the dominant lobe relative to a struck-wall click
    near = render(ImpactSequence([0.001], [-1], [1.0]), scene, model, LISTENER, sample_rate=fs, duration=0.01)
    assert np.dot(near.pressure[0], out.pressure[0]) < 0
    # walls="one": every impact is a struck-wall impact; struck_wall=+1 swaps the roles
    one = CavityScene("plane", radius=A, gap=gap, walls="one")
    same = render(ImpactSequence([0.001], [1], [1.0]), one, model, LISTENER, sample_rate=fs, duration=0.01)
    np.testing.assert_allclose(same.pressure, near.pressure, atol=1e-12)
    swapped = CavityScene("plane", radius=A, gap=gap, struck_wall=1)
    sw = render(ImpactSequence([0.001], [-1], [1.0]), swapped, model, LISTENER, sample_rate=fs, duration=0.01)
    np.testing.assert_allclose(sw.pressure, out.pressure, atol=1e-12)


def test_corner_sources_have_images_in_both_planes():
    scene = CavityScene(images_wall_floor(A, 0.05), gap=0.04)
    far = sound.wall_sources(scene, 1)
    assert len(far) == 4
    ref_cfg = images_wall_floor(A, 0.05)
    # the far sphere and its images are mirrored exactly like the struck sphere's
    for s_far, s_near in zip(far, ref_cfg.sources, strict=True):
        assert s_far.order == s_near.order
        np.testing.assert_allclose(np.abs(s_far.position[:2]), np.abs(s_near.position[:2]))
        np.testing.assert_allclose(s_far.axis, -s_near.axis)


def test_level_rises_with_speed_like_the_hertz_scaling():
    """Far-field pressure ~ A_max tau ~ U0 (peak ~ U0^{6/5}, duration ~ U0^{-1/5}) for a << c tau."""
    scene, model = CavityScene("free", radius=0.002), ClickModel(mass=1e-3, k_hertz=1e8)
    pt = np.array([0.0, 0.0, 1.0])
    e = [np.sum(render(ImpactSequence([0.001], [-1], [u]), scene, model, pt, sample_rate=96000).pressure ** 2)
         for u in (0.5, 1.0)]
    # the energy of a compact dipole is ∫ (dA/dt)² dt ~ A_max² / tau ~ U0^{12/5 + 1/5}
    assert e[1] / e[0] == pytest.approx(2 ** 2.6, rel=0.03)


# --------------------------------------------------------------------------- inputs
@pytest.mark.parametrize(
    "point, words",
    [((0.0, 0.0, 0.02), "inside the sphere"), ((0.5, 0.0, -0.01), "below the floor"),
     ((0.0, 0.0, 0.05), "inside the cavity")],
)
def test_bad_listeners_are_refused(point, words):
    with pytest.raises(ParameterError, match=words) as exc:
        sound.check_listeners(point, CavityScene("plane", radius=A), name="--listener")
    assert exc.value.name == "--listener"


def test_listener_behind_the_wall_is_refused():
    scene = CavityScene(images_wall_floor(A, 0.05))
    with pytest.raises(ParameterError, match="behind the wall"):
        render(ImpactSequence([0.0], [-1], [1.0]), scene, ClickModel(), [-0.2, 0.0, 0.3])


@pytest.mark.parametrize(
    "kwargs, name",
    [(dict(times=[0.1, -1.0], walls=[1, 1], velocities=[1, 1]), "times"),
     (dict(times=[0.1], walls=[0], velocities=[1]), "walls"),
     (dict(times=[0.1], walls=[1], velocities=[0.0]), "velocities"),
     (dict(times=[0.1, 0.2], walls=[1], velocities=[1]), "times")],
)
def test_bad_sequences_are_refused(kwargs, name):
    with pytest.raises(ParameterError) as exc:
        ImpactSequence(**kwargs)
    assert exc.value.name == name


def test_bad_settings_are_refused():
    seq, scene = ImpactSequence([0.0], [-1], [1.0]), CavityScene()
    with pytest.raises(ParameterError, match="sample_rate"):
        render(seq, scene, ClickModel(), LISTENER, sample_rate=22050)
    with pytest.raises(ParameterError, match="mass_model"):
        ClickModel(mass_model="both")
    with pytest.raises(ParameterError, match="walls"):
        CavityScene(walls="three")


def test_sequence_from_an_impact_table():
    table = {"time": [0.5, 0.1], "wall": [1.0, -1.0], "approach_velocity": [-1.2, 0.4]}
    seq = ImpactSequence.from_table(table)
    assert seq.velocities.tolist() == [1.2, 0.4] and seq.walls.tolist() == [1, -1]


def test_effective_mass_shortens_and_weakens_the_pulse():
    m, big_m = 0.0405, 0.5
    alone, eff = ClickModel(mass=m, main_mass=big_m), ClickModel(mass=m, main_mass=big_m, mass_model="effective")
    meff = m * big_m / (m + big_m)
    assert eff.pulse_for(1.0).duration / alone.pulse_for(1.0).duration == pytest.approx((meff / m) ** 0.4)
    assert eff.pulse_for(1.0).peak / alone.pulse_for(1.0).peak == pytest.approx((meff / m) ** 0.6)


def test_ears_are_symmetric_about_the_listener():
    scene = CavityScene("plane", radius=A)
    ears = sound.ear_positions(LISTENER, scene, spacing=0.18)
    assert np.linalg.norm(ears[0] - ears[1]) == pytest.approx(0.18)
    np.testing.assert_allclose(ears.mean(axis=0), LISTENER)
    look = scene.geometry.contact_point - LISTENER
    assert abs(np.dot(ears[0] - ears[1], look)) < 1e-12


# --------------------------------------------------------------------------- files
def _two_clicks():
    seq = ImpactSequence([0.01, 0.03], [-1, 1], [1.4, 0.6])
    return render(seq, CavityScene("plane", radius=A), ClickModel(mass=M), [LISTENER, [0.2, 0.3, 0.4]],
                  sample_rate=48000, duration=0.05)


def test_float_wav_is_in_pascals(tmp_path):
    out = _two_clicks()
    info = audio.write_wav(tmp_path / "a.wav", Signal(out.pressure[0], 48000))
    data, fs = sf.read(tmp_path / "a.wav", dtype="float64")
    meta = sf.info(str(tmp_path / "a.wav"))
    assert fs == 48000 and meta.subtype == "FLOAT" and meta.format == "WAV" and meta.channels == 1
    np.testing.assert_allclose(data, out.pressure[0], rtol=1e-7, atol=1e-7 * out.peak[0])
    assert info["pa_per_full_scale"] == 1.0 and info["clipped_samples"] == 0
    # the peak exceeds 1 Pa (94 dB): stored as it is, and said so
    assert info["over_full_scale_db"] == pytest.approx(20 * math.log10(out.peak[0]))


def _chunks(path) -> dict:
    """The chunks of a RIFF/WAVE file: id -> its bytes (after the 8-byte header)."""
    data = path.read_bytes()
    assert data[:4] == b"RIFF" and data[8:12] == b"WAVE"
    out, at = {}, 12
    while at + 8 <= len(data):
        size = int.from_bytes(data[at + 4:at + 8], "little")
        out[data[at:at + 4]] = data[at + 8:at + 8 + size]
        at += 8 + size + (size & 1)
    return out


def test_a_float_wav_holds_its_peaks_but_not_the_time_it_was_written(tmp_path):
    """libsndfile stamps a float WAV's PEAK chunk with the time of writing: the file keeps the peaks, stamped 0."""
    out = _two_clicks()
    audio.write_wav(tmp_path / "a.wav", Signal(out.pressure, 48000))
    peak = _chunks(tmp_path / "a.wav")[b"PEAK"]
    version, stamp = np.frombuffer(peak[:8], dtype="<u4")
    assert version == 1 and stamp == 0
    data, _ = sf.read(tmp_path / "a.wav", dtype="float32")  # frames x channels
    for ch in range(2):
        value = np.frombuffer(peak[8 + 8 * ch:12 + 8 * ch], dtype="<f4")[0]
        frame = int(np.frombuffer(peak[12 + 8 * ch:16 + 8 * ch], dtype="<u4")[0])
        assert value == np.max(np.abs(data[:, ch])) and abs(data[frame, ch]) == value
    audio.write_wav(tmp_path / "b.wav", Signal(out.pressure, 48000), subtype="PCM_24", scale=10.0)
    assert b"PEAK" not in _chunks(tmp_path / "b.wav") and b"data" in _chunks(tmp_path / "b.wav")


def test_pcm24_shares_one_scale_and_never_clips_silently(tmp_path):
    out = _two_clicks()
    scale = audio.shared_scale(out.pressure, headroom_db=1.0)
    assert scale == pytest.approx(out.peak.max() * 10 ** 0.05)
    for i in range(2):
        audio.write_wav(tmp_path / f"{i}.wav", Signal(out.pressure[i], 48000), subtype="PCM_24", scale=scale)
        data, _ = sf.read(tmp_path / f"{i}.wav", dtype="float64")
        assert sf.info(str(tmp_path / f"{i}.wav")).subtype == "PCM_24"
        np.testing.assert_allclose(data * scale, out.pressure[i], atol=scale * 2.0**-22)
    with pytest.warns(audio.ClippingWarning, match=r"dB over full scale"):
        info = audio.write_wav(tmp_path / "c.wav", Signal(out.pressure[0], 48000), subtype="PCM_24", scale=0.5)
    assert info["clipped_samples"] > 0
    assert info["over_full_scale_db"] == pytest.approx(20 * math.log10(out.peak[0] / 0.5))
    data, _ = sf.read(tmp_path / "c.wav")
    assert np.max(np.abs(data)) <= 1.0  # clipped, not wrapped around
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        audio.write_wav(tmp_path / "d.wav", Signal(out.pressure[0], 48000), subtype="FLOAT")  # float: no warning


def test_sidecar_is_beside_the_wav(tmp_path):
    out = _two_clicks()
    wav = tmp_path / "run.wav"
    info = audio.write_wav(wav, Signal(out.pressure, 48000))
    path = audio.write_sidecar(wav, {**out.describe(), "file": info})
    assert path == tmp_path / "run.json"
    rec = json.loads(path.read_text())
    assert rec["impact_count"] == 2 and rec["impact_count_by_wall"] == {"-1": 1, "+1": 1}
    assert rec["sample_rate_hz"] == 48000 and rec["file"]["subtype"] == "FLOAT"
    assert rec["scene"]["sources"]["+1"][0]["axis"] == [0.0, 0.0, -1.0]
    assert sf.info(str(wav)).channels == 2


@pytest.mark.skipif(shutil.which("sox") is None, reason="sox is not installed")
def test_sox_reads_the_files(tmp_path):
    """An independent reader sees the rate, channels and encoding, and the calibrated peak.

    sox converts float samples to integers on reading and so clips beyond +-1.0: the float file is
    checked with a scale of 10 Pa per unit (peaks about 0.27), the PCM file with the shared scale.
    """
    out = _two_clicks()
    scale = audio.shared_scale(out.pressure)
    audio.write_wav(tmp_path / "f.wav", Signal(out.pressure, 48000), scale=10.0)
    audio.write_wav(tmp_path / "p.wav", Signal(out.pressure, 48000), subtype="PCM_24", scale=scale)

    def sox(*args):
        res = subprocess.run(["sox", *map(str, args)], capture_output=True, text=True, check=True)
        return res.stdout + res.stderr

    f, p = sox("--i", tmp_path / "f.wav"), sox("--i", tmp_path / "p.wav")
    assert "Sample Rate    : 48000" in f and "32-bit Floating Point" in f and "Channels       : 2" in f
    assert "Sample Rate    : 48000" in p and "24-bit Signed Integer" in p
    for name, sc, tol in (("f.wav", 10.0, 1e-5), ("p.wav", scale, 1e-5)):  # sox prints 6 decimals
        stat = sox(tmp_path / name, "-n", "stat")
        top = float(next(ln for ln in stat.splitlines() if ln.startswith("Maximum amplitude")).split()[-1])
        low = float(next(ln for ln in stat.splitlines() if ln.startswith("Minimum amplitude")).split()[-1])
        assert top * sc == pytest.approx(out.pressure.max(), rel=tol)
        assert low * sc == pytest.approx(out.pressure.min(), rel=tol)


def test_silence_and_its_sidecar(tmp_path):
    out = render(ImpactSequence([], [], []), CavityScene(), ClickModel(), LISTENER, duration=0.1)
    assert out.n_samples >= 4800 and not np.any(out.pressure) and out.peak_spl[0] == -np.inf
    path = audio.write_sidecar(tmp_path / "s.wav", {"peak_spl_db_re_20upa": out.peak_spl, **out.describe()})
    rec = json.loads(path.read_text())  # strict JSON: -inf dB is written as null
    assert rec["peak_spl_db_re_20upa"] == [None] and rec["impact_count"] == 0


def test_figure_axes_carry_units():
    from acoustiviz.output.plot.audio import auralisation_figure

    out = _two_clicks()
    fig = auralisation_figure([Signal(p, out.sample_rate) for p in out.pressure], labels=["a", "b"])
    labels = {ax.get_xlabel() for ax in fig.axes} | {ax.get_ylabel() for ax in fig.axes}
    assert {"time (s)", "time (ms)", "sound pressure (Pa)", "frequency (kHz)"} <= labels
    assert any("dB re 20 µPa" in lab for lab in labels)  # the colour bars


@pytest.mark.skipif(field is None, reason="the field evaluator is not available")
def test_whole_run_level_and_exposure_match_the_field_evaluator():
    """A 3 s Table 1 run at 96 kHz: its peak is the loudest click's and its exposure the sum of the clicks'.

    Clicks last about 1.5 ms and impacts are more than 19 ms apart, so they do not overlap. The per-click
    reference is the field evaluator on an independently built configuration for each wall (the far wall's
    sphere at a + gap accelerating along -z, imaged in z = 0). Tolerances as for one click.
    """
    from acoustiviz.core.geometry import Configuration
    from acoustiviz.dynamics import TABLE1, simulate

    run = simulate(TABLE1, 3.0)
    seq = ImpactSequence.from_table(run.impacts)
    assert len(seq) > 30 and np.min(np.diff(np.sort(seq.times))) > 0.01
    scene, model = CavityScene("plane", radius=A, gap=TABLE1.gap), ClickModel(mass=TABLE1.m)
    out = render(seq, scene, model, LISTENER, sample_rate=96000)
    far = Configuration("plane", A, (ImageSource([0, 0, A + TABLE1.gap], [0, 0, -1], 0, "far"),
                                     ImageSource([0, 0, -A - TABLE1.gap], [0, 0, 1], 1, "floor")))
    configs = {-1: images_plane(A), 1: far}
    peaks, exposure = [], 0.0
    for w, u in zip(seq.walls, seq.velocities, strict=True):
        met = field.field_metrics(model.pulse_for(u), LISTENER[None, :], configs[int(w)])
        peaks.append(max(met.peak_positive[0], -met.peak_negative[0]))
        exposure += met.exposure[0]
    assert out.peak[0] == pytest.approx(max(peaks), rel=5e-3)
    assert np.sum(out.pressure[0] ** 2) / out.sample_rate == pytest.approx(exposure, rel=1e-4)


def test_wav_writer_takes_a_signal_of_whole_hertz(tmp_path):
    with pytest.raises(ParameterError, match="signal"):
        audio.write_wav(tmp_path / "a.wav", np.zeros(10))
    with pytest.raises(ParameterError, match="sample_rate"):
        audio.write_wav(tmp_path / "b.wav", Signal(np.zeros(10), 44100.5))
    assert not list(tmp_path.iterdir())  # refused before anything was written


def test_a_calibrated_wav_reads_back_as_the_signal_written(tmp_path):
    from acoustiviz.app.levels import read_calibrated_wav

    out = _two_clicks()
    path = tmp_path / "two.wav"
    audio.write_wav(path, out.signal, subtype="FLOAT", scale=0.5)
    back = read_calibrated_wav(path, pa_per_fs=0.5)
    sig = back.signal
    assert isinstance(sig, Signal) and sig.sample_rate == out.sample_rate == 48000 and sig.start == 0.0
    assert sig.channels == 2 and sig.n_samples == out.n_samples
    np.testing.assert_allclose(sig.pressure, out.pressure, rtol=1e-7, atol=1e-7 * out.peak.max())
    assert back.source == "given" and back.channels == ["1", "2"]


def test_a_rendering_carries_its_samples_as_one_signal():
    out = _two_clicks()
    assert isinstance(out.signal, Signal) and out.signal.channels == 2
    assert out.pressure is out.signal.pressure and not out.pressure.flags.writeable
    assert out.sample_rate == 48000 and isinstance(out.sample_rate, int)
    np.testing.assert_allclose(out.time, out.signal.times, rtol=0, atol=1e-15)


def test_plots_draw_a_signal_against_its_own_times():
    from acoustiviz.output.plot.audio import plot_pressure_signal, plot_spectrogram

    fs, t0 = 8000, 2.0
    sig = Signal(np.sin(2 * np.pi * 500 * np.arange(fs // 2) / fs), fs, start=t0)
    ax = plot_pressure_signal(sig)
    assert ax.get_xlim() == pytest.approx((t0, t0 + (fs // 2 - 1) / fs))
    ax = plot_spectrogram(sig, segment=0.01)
    lo, hi = ax.get_xlim()
    assert t0 <= lo < t0 + 0.01 and t0 + 0.49 < hi <= t0 + 0.5
    with pytest.raises(ParameterError, match="signal"):
        plot_pressure_signal(Signal(np.zeros((2, 10)), fs))  # one channel per plot
