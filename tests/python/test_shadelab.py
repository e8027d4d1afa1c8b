"""The Python module against the double references and the command line's contracts.

Run by ctest (python.module) with the built module on PYTHONPATH.
"""
import math
import os

import numpy as np
import pytest

import shadelab

MESHES = os.environ.get("SHADELAB_MESH_DIR", "")


def hemisphere(n, seed):
    """n unit vectors uniform in solid angle on the upper hemisphere (z >= 0)."""
    rng = np.random.default_rng(seed)
    z = rng.random(n)
    phi = rng.random(n) * 2 * math.pi
    r = np.sqrt(1 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(np.float32)


def test_models_lists_the_catalogue():
    names = shadelab.models()
    assert "lambert" in names and "oren_nayar" in names and len(names) == len(set(names)) > 30
    info = shadelab.model_info("oren_nayar")
    assert [p["name"] for p in info["params"]] == ["sigma"]


@pytest.mark.parametrize("model,params", [
    ("lambert", {}),
    ("oren_nayar", {"sigma": 0.6}),
    ("minnaert_1941", {"k": 0.8}),
    ("blinn_phong", {"n": 40.0}),
    ("cook_torrance_ggx", {"m": 0.3}),
])
def test_shade_matches_the_double_reference_over_a_sweep(model, params):
    n = 20000
    N = np.tile(np.array([[0, 0, 1]], np.float32), (n, 1))
    L, V = hemisphere(n, 1), hemisphere(n, 2)
    got = shadelab.shade(model, N, L, V, **params)
    assert got.dtype == np.float32 and got.shape == (n, 3)
    ref = shadelab.reference(model, N, L, V, **params)
    assert ref.dtype == np.float64 and ref.shape == (n, 3)
    assert np.all(np.isfinite(got))
    err = np.abs(got - ref) / np.maximum(1.0, np.abs(ref))
    assert np.percentile(err, 99) < 1e-4, (model, float(np.percentile(err, 99)), float(err.max()))


def test_lambert_is_the_cosine_for_albedo_one():
    n = 1000
    N = np.tile(np.array([[0, 0, 1]], np.float32), (n, 1))
    L = hemisphere(n, 3)
    out = shadelab.shade("lambert", N, L, N)
    np.testing.assert_allclose(out[:, 0], L[:, 2], rtol=1e-6, atol=1e-7)


def test_errors_are_python_exceptions_with_one_line():
    N = np.zeros((2, 3), np.float32)
    with pytest.raises(shadelab.Error, match="unknown model 'minaert' \\(did you mean 'minnaert_1941'\\?\\)"):
        shadelab.shade("minaert", N, N, N)
    with pytest.raises(shadelab.Error, match="has no parameter 'kk'"):
        shadelab.shade("minnaert_1941", N, N, N, kk=1.0)
    with pytest.raises(shadelab.Error, match="shape \\(n, 3\\)"):
        shadelab.shade("lambert", np.zeros((2, 4), np.float32), N, N)
    bad = N.copy()
    bad[1, 0] = np.nan
    with pytest.raises(shadelab.Error, match="NaN or Inf"):
        shadelab.shade("lambert", bad, N, N)


@pytest.mark.skipif(not MESHES, reason="SHADELAB_MESH_DIR not set")
def test_render_then_compare_and_fit_a_disc():
    img = shadelab.render(os.path.join(MESHES, "spot.obj"), width=96, height=64, model="oren_nayar", sigma=0.3)
    assert img.shape == (64, 96, 4) and img.dtype == np.float32
    assert (img[..., 3] > 0.5).sum() > 500 and np.all(np.isfinite(img))
    same = shadelab.compare(img, img)
    assert same["de2000_max"] == 0.0 and same["pixels"] == (img[..., 3] > 0).sum()
    other = shadelab.render(os.path.join(MESHES, "spot.obj"), width=96, height=64, model="lambert")
    assert shadelab.compare(other, img)["de2000_mean"] > 0.1


def test_moon_fit_recovers_minnaert_k_on_a_synthetic_disc():
    # An independent disc in numpy: Minnaert's law I = B0 mu0^k mu^(k-1) at phase 0 (mu0 = mu), k = 0.7.
    size, R, k, B0 = 201, 90.0, 0.7, 0.4
    y, x = np.mgrid[0:size, 0:size].astype(np.float64)
    X, Y = (x + 0.5 - 100.5) / R, (100.5 - (y + 0.5)) / R
    rho2 = X * X + Y * Y
    mu = np.sqrt(np.clip(1 - rho2, 0, 1))
    I = np.where(rho2 < 1, B0 * mu ** k * np.maximum(mu, 1e-9) ** (k - 1), 0.0).astype(np.float32)
    fit = shadelab.moon_fit(I, cx=100.5, cy=100.5, radius=R, phase=0.0)
    assert abs(fit["k"] - k) < 1e-3 and abs(fit["B0"] - B0) < 1e-3 * B0, fit
    assert fit["pixels"] > 1000
