"""pk.load_height / pk.load_albedo: files written here with Pillow (8-bit, 16-bit, float TIFF)
and OpenEXR, read back by the core's `image` crate; values checked to the file's precision."""

import numpy as np
import pytest
from PIL import Image

import pomkit as pk

RNG = np.random.default_rng(7)


def test_8bit_png_height(tmp_path):
    a = RNG.integers(0, 256, (17, 23), dtype=np.uint8)
    Image.fromarray(a).save(tmp_path / "h.png")
    h = pk.load_height(tmp_path / "h.png")
    assert h.dtype == np.float32 and h.shape == (17, 23)
    assert np.array_equal(h, a.astype(np.float32) / 255.0)


@pytest.mark.parametrize("ext", ["png", "tif"])
def test_16bit_height_keeps_every_level(tmp_path, ext):
    a = RNG.integers(0, 65536, (19, 21), dtype=np.uint16)
    a[0, 0], a[0, 1] = 30000, 30001  # adjacent 16-bit levels stay distinct
    Image.fromarray(a).save(tmp_path / f"h.{ext}")
    h = pk.load_height(tmp_path / f"h.{ext}")
    assert np.array_equal(h, a.astype(np.float32) / 65535.0)
    assert h[0, 0] != h[0, 1]
    # and it makes a Material that renders
    assert pk.Material(h).height.shape == (19, 21)


def test_float_tiff_height_keeps_its_values(tmp_path):
    a = RNG.random((9, 11), dtype=np.float32)
    Image.fromarray(a).save(tmp_path / "h.tif")
    assert np.array_equal(pk.load_height(tmp_path / "h.tif"), a)


def test_exr_height_and_albedo(tmp_path):
    OpenEXR = pytest.importorskip("OpenEXR", reason="the test extra's openexr writes the file")
    a = RNG.random((8, 10), dtype=np.float32)
    rgb = RNG.random((8, 10, 3), dtype=np.float32) * 2.0
    for name, pix in (("h.exr", np.repeat(a[..., None], 3, -1)), ("c.exr", rgb)):
        channels = {"RGB": np.ascontiguousarray(pix)}
        with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, channels) as f:
            f.write(str(tmp_path / name))
    assert np.array_equal(pk.load_height(tmp_path / "h.exr"), a)
    al = pk.load_albedo(tmp_path / "c.exr")
    assert np.array_equal(al, rgb)  # float files are linear already


def test_8bit_albedo_is_decoded_from_srgb(tmp_path):
    a = RNG.integers(0, 256, (6, 7, 3), dtype=np.uint8)
    Image.fromarray(a).save(tmp_path / "c.png")
    al = pk.load_albedo(tmp_path / "c.png")
    assert al.shape == (6, 7, 3) and al.dtype == np.float32
    np.testing.assert_allclose(al, pk.srgb_to_linear(a / 255.0), rtol=0, atol=1e-6)
    # the same as Material's own decoding of a uint8 sRGB array
    np.testing.assert_allclose(pk.Material(np.zeros((6, 7), np.float32), albedo=a).albedo, al, atol=1e-6)


def test_colour_height_map_is_refused(tmp_path):
    a = RNG.integers(0, 256, (5, 5, 3), dtype=np.uint8)
    Image.fromarray(a).save(tmp_path / "colour.png")
    with pytest.raises(ValueError, match="colour.png.*greyscale"):
        pk.load_height(tmp_path / "colour.png")
    grey = np.repeat(a[..., :1], 3, -1)
    Image.fromarray(grey).save(tmp_path / "grey_rgb.png")
    assert np.array_equal(pk.load_height(tmp_path / "grey_rgb.png"), grey[..., 0] / np.float32(255.0))


@pytest.mark.parametrize("content, why", [(None, "cannot open"), (b"not an image at all", "cannot decode"),
                                          (b"\x89PNG\r\n\x1a\n" + b"\x00" * 20, "cannot decode")])
def test_bad_files_name_the_path_and_the_reason(tmp_path, content, why):
    p = tmp_path / "bad.png"
    if content is not None:
        p.write_bytes(content)
    with pytest.raises(ValueError, match=f"path: .*bad.png: {why}"):
        pk.load_height(p)
    with pytest.raises(TypeError, match="path"):
        pk.load_height(3)
