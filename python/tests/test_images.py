"""read, write and compare: images and the metrics of `caustica compare`."""

import numpy as np
import pytest

import caustica


@pytest.fixture(scope="module")
def pair():
    s = caustica.load("caustic-box")
    a, _ = caustica.render(s, integrator="path", spp=2, width=48, seed=1)
    b, _ = caustica.render(s, integrator="path", spp=8, width=48, seed=2)
    return a, b


@pytest.mark.parametrize("ext", ["exr", "pfm"])
def test_float_images_round_trip_bit_for_bit(tmp_path, pair, ext):
    p = tmp_path / f"img.{ext}"
    caustica.write(p, pair[0])
    back = caustica.read(p)
    assert np.array_equal(back.view(np.uint32), pair[0].view(np.uint32))


def test_png_is_the_cli_png(cli, tmp_path, pair):
    caustica.write(tmp_path / "a.exr", pair[0])
    caustica.write(tmp_path / "py.png", pair[0], exposure=1.0)
    cli("convert", tmp_path / "a.exr", tmp_path / "cli.png", "--exposure", "1")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def _cli_metrics(text):
    rows = {}
    for line in text.splitlines():
        key, _, value = line.partition("  ")
        rows[key.strip()] = value.strip()
    return rows


def test_compare_gives_the_cli_metrics(cli, tmp_path, pair):
    a, b = pair
    caustica.write(tmp_path / "a.exr", a)
    caustica.write(tmp_path / "b.exr", b)
    mask = np.zeros(a.shape[:2], np.float32)
    mask[8:40, 4:44] = 1
    caustica.write(tmp_path / "mask.exr", np.repeat(mask[:, :, None], 3, axis=2))
    for args, kwargs in [([], {}), (["--crop", "2,3,30,20"], dict(crop=(2, 3, 30, 20))),
                         (["--mask", tmp_path / "mask.exr", "--exposure", "-1"], dict(mask=mask, exposure=-1.0))]:
        r = _cli_metrics(cli("compare", tmp_path / "a.exr", tmp_path / "b.exr", *args).stdout)
        m = caustica.compare(a, b, **kwargs)
        assert int(r["pixels"]) == m["pixels"]
        assert float(r["RMSE"]) == pytest.approx(m["rmse"], abs=5e-7)
        assert float(r["relative MSE"]) == pytest.approx(m["relative_mse"], abs=5e-7)
        assert float(r["MISE (display)"]) == pytest.approx(m["mise"], abs=5e-7)
        assert float(r["SSIM (display)"]) == pytest.approx(m["ssim"], abs=5e-6)
        assert float(r["relative mean difference"]) == pytest.approx(m["relative_mean_difference"], abs=5e-6)


def test_an_image_against_itself():
    img = np.random.default_rng(3).random((20, 30, 3), dtype=np.float32)
    m = caustica.compare(img, img)
    assert m["rmse"] == 0 and m["relative_mean_difference"] == 0 and m["block_z"]["flagged"] == 0
    assert m["ssim"] == pytest.approx(1.0)


def test_bad_images_are_refused(tmp_path):
    with pytest.raises(ValueError, match="shape"):
        caustica.compare(np.zeros((4, 4)), np.zeros((4, 4, 3)))
    with pytest.raises(TypeError, match="'image'"):
        caustica.compare("a.exr", np.zeros((4, 4, 3)))
    with pytest.raises(ValueError, match="size"):
        caustica.compare(np.zeros((4, 5, 3)), np.zeros((4, 4, 3)))
    with pytest.raises(OSError, match="missing.exr"):
        caustica.read(tmp_path / "missing.exr")
    with pytest.raises(ValueError, match="expected .exr, .pfm or .png"):
        caustica.write(tmp_path / "x.tiff", np.zeros((2, 2, 3)))
