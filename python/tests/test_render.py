"""A render from Python is the command line's render: the same bits, the same messages."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import caustica

# (scene, CLI arguments, Python keyword arguments): small renders of every family.
CASES = [
    ("caustic-box", ["--integrator", "path", "--spp", "2", "--width", "40"],
     dict(integrator="path", spp=2, width=40)),
    ("water-wave", ["--integrator", "pds", "--photons", "4000", "--spp", "2", "--width", "48", "--seed", "7"],
     dict(integrator="pds", photons=4000, spp=2, width=48, seed=7)),
    ("glass-sphere", ["--integrator", "pm", "--photons", "3000", "--spp", "1", "--width", "32", "--k", "20"],
     dict(integrator="pm", photons=3000, spp=1, width=32, k=20)),
    ("caustic-box", ["--integrator", "lighttrace", "--spp", "1", "--width", "32", "--caustics-only"],
     dict(integrator="lighttrace", spp=1, width=32, caustics_only=True)),
    ("caustic-box", ["--integrator", "pppm", "--iterations", "3", "--photons-per-iteration", "2000",
                     "--width", "32", "--ppm-alpha", "0.6"],
     dict(integrator="pppm", iterations=3, photons_per_iteration=2000, width=32, ppm_alpha=0.6)),
    ("scenes/mitsuba/cornell-box.xml", ["-D", "res=24", "-D", "spp=2", "--crop", "4,6,12,10"],
     dict(crop=(4, 6, 12, 10))),
]


@pytest.mark.parametrize("scene,args,kwargs", CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_render_equals_the_cli_exr_bit_for_bit(cli, root, tmp_path, scene, args, kwargs):
    out = tmp_path / "cli.exr"
    cli("render", scene, *args, "-o", out, "-q")
    expected = caustica.read(out)
    defaults = {}
    if scene.endswith(".xml"):
        defaults = dict(res=24, spp=2)
        scene = str(root / scene)
    image, notes = caustica.render(caustica.load(scene, **defaults), **kwargs)
    assert image.dtype == np.float32 and image.shape == expected.shape
    assert np.array_equal(image.view(np.uint32), expected.view(np.uint32))
    if "integrator" in kwargs:
        assert notes["integrator"] == kwargs["integrator"]
    assert image.any()


def test_the_thread_count_does_not_change_the_image():
    s = caustica.load("water-wave")
    a, _ = caustica.render(s, integrator="pds", photons=3000, spp=1, width=40, threads=1)
    b, _ = caustica.render(s, integrator="pds", photons=3000, spp=1, width=40, threads=2)
    assert np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_notes_report_the_render():
    img, notes = caustica.render("caustic-box", integrator="path", spp=3, width=20, seed=5)
    assert notes["scene"] == "caustic-box" and notes["seed"] == 5
    assert notes["spp"] == pytest.approx(3.0)
    assert notes["width"] == 20 and img.shape[1] == 20
    assert notes["samples"] == 3 * img.shape[0] * img.shape[1]
    assert notes["seconds"] > 0 and notes["rays"] > 0


def _message(r):
    """The CLI's error message: its `error: ` line without `error: ` (clap adds a hint line)."""
    lines = [x for x in r.stderr.splitlines() if x.startswith("error: ")]
    assert len(lines) == 1, r.stderr
    return lines[0][len("error: "):]


def test_a_missing_scene_file_is_an_oserror_with_the_cli_message(cli, tmp_path):
    missing = tmp_path / "missing.toml"
    r = cli("render", missing, "-q", "-o", tmp_path / "x.exr", check=False)
    assert r.returncode != 0
    with pytest.raises(OSError) as e:
        caustica.load(missing)
    assert str(e.value) == _message(r)


def test_a_malformed_scene_is_a_valueerror_with_line_and_column(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[camera]\nfov = "wide"\n')
    r = cli("render", bad, "-q", "-o", tmp_path / "x.exr", check=False)
    with pytest.raises(ValueError) as e:
        caustica.load(bad)
    assert str(e.value) == _message(r)
    assert f"{bad}:2:" in str(e.value)


@pytest.mark.parametrize("args,kwargs", [
    (["--spp", "0"], dict(spp=0)),
    (["--integrator", "nope"], dict(integrator="nope")),
    (["--spp", "-3"], dict(spp=-3)),
    (["--time", "2", "--spp", "4", "--integrator", "path"], dict(time=2, spp=4, integrator="path")),
    (["--kernel", "no-such-kernel", "--integrator", "pm"], dict(kernel="no-such-kernel", integrator="pm")),
    (["--crop", "30,0,8,8", "--width", "32"], dict(crop=(30, 0, 8, 8), width=32)),
])
def test_bad_values_are_valueerrors_with_the_cli_message(cli, tmp_path, args, kwargs):
    r = cli("render", "caustic-box", *args, "-q", "-o", tmp_path / "x.exr", check=False)
    assert r.returncode != 0
    with pytest.raises(ValueError) as e:
        caustica.render(caustica.load("caustic-box"), **kwargs)
    assert str(e.value) == _message(r)


@pytest.mark.parametrize("kwargs,name", [
    (dict(spp="16"), "spp"),
    (dict(spp=2.5), "spp"),
    (dict(smoothing="wide"), "smoothing"),
    (dict(caustics_only=1), "caustics_only"),
    (dict(no_such_option=3), "no_such_option"),
    (dict(smothing=2.0), "smothing"),
    (dict(threads="2"), "threads"),
    (dict(crop=(1, 2, 3)), "crop"),
    (dict(integrator=["pm"]), "integrator"),
    (dict(define="x=1"), "define"),
])
def test_wrong_argument_types_and_names_are_typeerrors_naming_them(kwargs, name):
    given = dict(spp=1, width=8)
    given.update(kwargs)
    with pytest.raises(TypeError) as e:
        caustica.render(caustica.load("caustic-box"), **given)
    assert f"'{name}'" in str(e.value)


def test_a_misspelt_option_gets_a_suggestion():
    with pytest.raises(TypeError, match="did you mean 'smoothing'"):
        caustica.render("caustic-box", smothing=2.0)


def test_load_takes_mitsuba_defaults_and_checks_them(root):
    s = caustica.load(root / "scenes/mitsuba/cornell-box.xml", res=16)
    assert (s.width, s.height) == (16, 16)
    with pytest.raises(ValueError, match="no parameter 'nope'"):
        caustica.load(root / "scenes/mitsuba/cornell-box.xml", nope=1)
    with pytest.raises(TypeError, match="'res'"):
        caustica.load(root / "scenes/mitsuba/cornell-box.xml", res=[16])


def test_keyboard_interrupt_stops_a_render_promptly():
    s = caustica.load()
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        # Far longer than the test, but finite: without the interrupt it would end after 15 s.
        caustica.render(s, integrator="path", time=15.0, width=64)
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 1.0 + 3.0, f"the render went on for {elapsed - 1.0:.2f} s after Ctrl-C"


def test_the_gil_is_released_during_a_render():
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.002)

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.05)
    start = time.monotonic()
    # A time budget, not a sample count: the render lasts about a second however fast the
    # machine (64 spp took 0.23 s on a quiet one, too short to tell).
    caustica.render("caustic-box", integrator="path", time=1.0, width=64)
    end = time.monotonic()
    done.set()
    t.join()
    assert end - start > 0.3, "the render is too short to tell"
    inside = [x for x in ticks if start + 0.05 < x < end - 0.05]
    # Holding the GIL for the whole call would leave the other thread no tick at all inside it;
    # released, it ticks about every 2 ms (at least 10 even on a machine busy elsewhere).
    assert len(inside) >= 10, len(inside)


def test_a_pbrt_v4_scene_renders_as_its_mitsuba_version(root):
    kw = dict(integrator="path", spp=2, width=24, seed=3)
    a, _ = caustica.render(caustica.load(root / "scenes/pbrt-v4/cornell-box.pbrt"), **kw)
    b, _ = caustica.render(caustica.load(root / "scenes/mitsuba/cornell-box.xml"), **kw)
    assert a.any() and np.array_equal(a.view(np.uint32), b.view(np.uint32))
