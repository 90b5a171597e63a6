"""``tessella.render``: offscreen pictures of the refined surface, coloured by a per-vertex field
with a colour bar (the CLI's ``tessella render --color-by --colormap --range``).

The colours are checked against the colormaps' own samples (matplotlib's, as in
``crates/tessella-view/src/colormap.rs``): the shader lights a field's colour diffusely (a
scale of its linear RGB), so a pixel is matched to the colormap colour of the same direction
in linear RGB.

These tests need a GPU adapter; Mesa's lavapipe serves (CI installs it). They fail, not skip,
when none exists.
"""

import numpy as np
import pytest

import tessella
from conftest import icosphere

VIRIDIS = np.array([
    [68, 1, 84], [72, 24, 106], [71, 45, 123], [66, 64, 134], [59, 82, 139], [51, 99, 141],
    [44, 114, 142], [38, 130, 142], [33, 145, 140], [31, 160, 136], [40, 174, 128],
    [63, 188, 115], [94, 201, 98], [132, 212, 75], [173, 220, 48], [216, 226, 25],
    [253, 231, 37],
], dtype=np.float64)
COOLWARM = np.array([
    [59, 76, 192], [78, 104, 216], [98, 130, 234], [119, 154, 247], [141, 176, 254],
    [163, 194, 254], [185, 208, 249], [204, 217, 237], [221, 220, 220], [236, 211, 197],
    [245, 196, 172], [247, 176, 147], [244, 152, 122], [235, 125, 98], [221, 95, 75],
    [202, 59, 55], [180, 4, 38],
], dtype=np.float64)


def linear(srgb):
    c = np.asarray(srgb, dtype=np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def t_of(pixels, samples):
    """The colormap position (0..1) of each RGB pixel: the finely interpolated colormap colour
    whose linear-RGB direction is nearest (lighting only scales a colour)."""
    t = np.linspace(0, 1, 1025)
    s = t * (len(samples) - 1)
    k = np.minimum(np.floor(s).astype(int), len(samples) - 2)
    ramp = samples[k] + (samples[k + 1] - samples[k]) * (s - k)[:, None]
    unit = lambda a: a / np.linalg.norm(a, axis=-1, keepdims=True)  # noqa: E731
    cos = unit(linear(pixels)) @ unit(linear(ramp)).T
    return t[np.argmax(cos, axis=1)]


def square(n=4):
    """A vertical unit square in the x-y plane facing +z (the camera at yaw 0, pitch 0)."""
    xs = np.linspace(-1, 1, n + 1)
    v = np.array([[x, y, 0.0] for y in xs for x in xs])
    f = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            f += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return v, np.array(f), np.tile([0.0, 0.0, 1.0], (len(v), 1))


def surface_mask(img, width):
    """Pixels of the surface: left of the bar (first `width` columns), not the white background."""
    rgb = img[:, :width, :3].astype(int)
    return rgb.sum(axis=2) < 3 * 245


def test_higher_pixels_are_hotter_on_a_vertical_square():
    v, f, n = square()
    img = tessella.render(v, f, n, scheme="flat", level=4, size=(400, 300), yaw=0, pitch=0,
                          point_data={"T": v[:, 1]}, color_by="T")
    assert img.shape == (300, 400, 4) and img.dtype == np.uint8
    width = 400 - 84  # the bar of a picture 300 pixels tall is 84 pixels wide
    mask = surface_mask(img, width)
    rows = np.flatnonzero(mask.any(axis=1))
    assert len(rows) > 150, "the square fills most of the height"
    rows = rows[2:-2]  # the edges' rows blend with the background (multisampling)
    # Per row (top first), the median colormap position of its surface pixels.
    ts = np.array([np.median(t_of(img[r, :width, :3][mask[r]], VIRIDIS)) for r in rows])
    assert np.all(np.diff(ts) <= 0.02), "T must not rise going down the picture"
    assert ts[0] > 0.9 and ts[-1] < 0.1, (ts[0], ts[-1])
    # T = y is linear in height on a square seen head-on: the colour position follows the row.
    expected = np.interp(rows, [rows[0], rows[-1]], [ts[0], ts[-1]])
    assert np.abs(ts - expected).max() < 0.06


def test_sphere_top_is_hotter_than_its_bottom_with_coolwarm():
    v, f = icosphere(2)
    img = tessella.render(v, f, v, level=6, size=(360, 300), yaw=0, pitch=0,
                          point_data={"T": v[:, 1]}, color_by="T", colormap="coolwarm")
    width = 360 - 84
    mask = surface_mask(img, width)
    rows = np.flatnonzero(mask.any(axis=1))
    third = len(rows) // 3
    top = t_of(img[rows[:third], :width, :3][mask[rows[:third]]], COOLWARM)
    bottom = t_of(img[rows[-third:], :width, :3][mask[rows[-third:]]], COOLWARM)
    assert np.median(top) > 0.75 and np.median(bottom) < 0.25, (np.median(top), np.median(bottom))


@pytest.mark.parametrize("name,samples", [("viridis", VIRIDIS), ("coolwarm", COOLWARM)])
def test_the_colour_bar_spans_the_colormap(name, samples):
    v, f, n = square(2)
    img = tessella.render(v, f, n, scheme="flat", level=1, size=(300, 240), yaw=0, pitch=0,
                          point_data={"T": v[:, 1]}, color_by="T", colormap=name,
                          range=(-2.0, 5.0))
    rgb = img[:, :, :3].astype(int)
    coloured = (rgb.max(axis=2) - rgb.min(axis=2)) > 30
    col = np.flatnonzero(coloured.any(axis=0))[-1]
    assert col >= 300 - 84, "the rightmost coloured column is in the bar"
    ys = np.flatnonzero(coloured[:, col])
    top, bottom = rgb[ys[0], col], rgb[ys[-1], col]
    assert np.abs(top - samples[-1]).max() <= 3, top  # high at the top
    assert np.abs(bottom - samples[0]).max() <= 3, bottom
    # Without the bar the picture is the surface alone, as wide as asked.
    bare = tessella.render(v, f, n, scheme="flat", level=1, size=(300, 240), yaw=0, pitch=0,
                           point_data={"T": v[:, 1]}, color_by="T", colormap=name,
                           colorbar=False)
    assert bare.shape == (240, 300, 4)
    rgb = bare[:, 250:, :3].astype(int)
    assert not ((rgb.max(axis=2) - rgb.min(axis=2)) > 30).any(), "no bar on the right"


def test_unknown_field_names_the_available_ones():
    v, f, n = square(1)
    with pytest.raises(ValueError, match=r'"P".*it has T, height'):
        tessella.render(v, f, n, point_data={"T": v[:, 1], "height": v[:, 0]}, color_by="P")
    with pytest.raises(ValueError, match="it has none"):
        tessella.render(v, f, n, color_by="T")


def test_bad_options_are_value_errors_with_the_core_messages():
    v, f, n = square(1)
    pd = {"T": v[:, 1]}
    with pytest.raises(ValueError, match=r'unknown colormap "nope"; use one of \["viridis", "coolwarm"\]'):
        tessella.render(v, f, n, point_data=pd, color_by="T", colormap="nope")
    for bad in [(3.0, 1.0), (0.0, float("nan"))]:
        with pytest.raises(ValueError, match="min < max"):
            tessella.render(v, f, n, point_data=pd, color_by="T", range=bad)
    with pytest.raises(ValueError, match="picture size 0x10"):
        tessella.render(v, f, n, size=(0, 10))
    with pytest.raises(ValueError, match="size="):
        tessella.render(v, f, n, size=(-1, 10))
    with pytest.raises(ValueError, match="no room beside"):
        tessella.render(v, f, n, point_data=pd, color_by="T", size=(50, 300))
    with pytest.raises(ValueError, match="components"):
        tessella.render(v, f, n, point_data={"V": v}, color_by="V")
    with pytest.raises(ValueError, match="tessella.schemes"):
        tessella.render(v, f, n, scheme="bezier")
    with pytest.raises(ValueError, match="rows"):
        tessella.render(v, f, n, point_data={"T": [1.0, 2.0]}, color_by="T")


def test_six_column_faces_render_quadratic_with_their_mid_node_field(tmp_path):
    # One P2 triangle whose mid-edge nodes bulge out; T is 1 at the mid nodes only.
    v = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0], [0, -1.2, 0.3], [0.6, 0.1, 0.3], [-0.6, 0.1, 0.3]])
    f = np.array([[0, 1, 2, 3, 4, 5]])
    t = np.array([0, 0, 0, 1, 1, 1.0])
    path = tmp_path / "p2.png"
    img = tessella.render(v, f, level=8, size=(300, 240), yaw=0, pitch=0,
                          point_data={"T": t}, color_by="T", path=path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert img.shape == (240, 300, 4)
    mask = surface_mask(img, 300 - 84)
    assert mask.sum() > 2000
    ts = t_of(img[:, : 300 - 84, :3][mask], VIRIDIS)
    # The quadratic field spans 0 (corners) .. 1 (mid nodes) .. 1/3 (centroid): both ends show.
    assert ts.min() < 0.15 and ts.max() > 0.85
    # The corners alone: a plain linear triangle.
    plain = tessella.render(v, f[:, :3], size=(200, 200), scheme="flat", level=1)
    assert plain.shape == (200, 200, 4)


def test_compare_panels_and_label(tmp_path):
    v, f = icosphere(1)
    img = tessella.render(v, f, v, compare=["flat", "pn"], level=4, size=(420, 200),
                          point_data={"T": v[:, 1]}, color_by="T", wireframe=True, label="x")
    assert img.shape == (200, 420, 4)
    with pytest.raises(ValueError, match="at least one panel"):
        tessella.render(v, f, v, compare=[])
    plain = tessella.render(v, f, v, size=(128, 96), path=tmp_path / "s.png")
    assert plain.shape == (96, 128, 4) and (tmp_path / "s.png").exists()
    # The default surface colour, no field: no bar, mostly the surface's blue.
    assert (plain[:, :, 2].astype(int) - plain[:, :, 0] > 40).sum() > 500
