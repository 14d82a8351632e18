"""The light pass's stored light and the stone model as arrays, checked against independent
numbers: Fresnel's normal-incidence transmittance, the energy ledger, the density estimate's
independence of the number of rays, the domains' diameter law and the ellipsoid."""

import numpy as np
import pytest

import opalray
from conftest import small_scene


def face_on(**changes):
    # Light and camera on the broad face's normal: the light enters the top of the stone
    # at normal incidence.
    return small_scene(camera={"tilt_deg": 0.0}, light={"angle_deg": 0.0}, **changes)


def test_light_pass_arrays_have_their_axes_and_match_the_render():
    scene = face_on()
    stages = opalray.prepare(scene)
    light = stages.light_pass()
    s = stages.structure
    bins = scene["spectrum"]["bins"]
    slots = (s.cells != s.OUTSIDE).sum()
    assert light.fluence.shape == (slots, 3, bins) and light.fluence.dtype == np.float32
    assert light.directions.shape == (slots, 3, 3) and light.concentration.shape == (slots, 3)
    assert light.LOBES == ("direct", "down", "up")
    np.testing.assert_array_equal(light.wavelengths_nm, stages.optics.wavelengths_nm)
    # Every inside cell once, in storage order, with its kind.
    assert (np.diff(light.cells) > 0).all()
    z, y, x = light.cell_zyx.T
    np.testing.assert_array_equal(light.kinds, s.cells[z, y, x])
    assert set(np.unique(light.kinds)) == {s.VOID, s.CLUSTER}
    assert np.isfinite(light.fluence).all() and (light.fluence >= 0).all()
    # Directions are unit where light arrived, and the scattered lobes go their way in z.
    lit = light.fluence.sum(axis=2) > 0
    np.testing.assert_allclose(np.linalg.norm(light.directions[lit], axis=-1), 1, atol=1e-4)
    down, up = light.directions[:, 1, 2], light.directions[:, 2, 2]
    assert (down[lit[:, 1]] <= 1e-6).all() and (up[lit[:, 2]] >= -1e-6).all()
    assert ((light.concentration >= 0) & (light.concentration <= 1 + 1e-6)).all()
    # The ledger balances (emitted = reflected + escaped + stored + absorbed + truncated)
    # and is the one the render at that angle reports.
    e = light.ledger
    booked = e["reflected"] + e["escaped"] + e["stored"] + e["absorbed"] + e["truncated"]
    assert booked == pytest.approx(e["emitted"], rel=1e-6)
    assert e == stages.render(0.0).stats["energy"]
    # On the grid: zero outside, the slots' values inside.
    grid = light.on_grid()
    assert grid.shape == s.cells.shape + (bins,)
    assert (grid[s.cells == s.OUTSIDE] == 0).all()
    np.testing.assert_allclose(grid[z, y, x], light.fluence.sum(axis=1), rtol=1e-6)
    # The same light on one thread as on every core; the module function is the method.
    one = stages.light_pass(0.0, threads=1)
    np.testing.assert_array_equal(one.fluence, light.fluence)
    np.testing.assert_array_equal(opalray.light_pass(scene).fluence, light.fluence)
    with pytest.raises(ValueError, match="light_angle_deg"):
        stages.light_pass(95.0)


def test_direct_light_under_the_face_is_fresnel_transmitted():
    # At normal incidence a collimated beam keeps its cross-section, so the direct fluence
    # just inside the face is the irradiance times Fresnel's T = 1 − ((n − 1)/(n + 1))²
    # (Born & Wolf §1.5.3), in the bins where no cluster near it reflects; nowhere more.
    stages = opalray.prepare(face_on())
    light = stages.light_pass()
    s, o = stages.structure, stages.optics
    n = o.n_eff
    fresnel_t = 1 - ((n - 1) / (n + 1)) ** 2
    # Bins far from the face-on Bragg line.
    clear = o.transmittance[0] > 0.999
    assert 0 < clear.sum() < len(clear)
    direct = light.on_grid("direct")
    nx, ny, nz = s.grid
    for x, y in [(nx // 2, ny // 2), (nx // 2 - 1, ny // 2), (nx // 2, ny // 2 - 1)]:
        z = np.nonzero(s.cells[:, y, x])[0].max()   # the top inside cell of the column
        ratio = direct[z, y, x] / light.light_spectrum
        # Blended with the cells around it (`light_pass/smooth.rs`), which see the light
        # filtered by the clusters above them: where none has a line, it is Fresnel's.
        matching = np.abs(ratio / fresnel_t - 1) < 2e-4
        assert matching.sum() >= 0.75 * len(ratio), (ratio, fresnel_t)
        assert ratio.max() <= fresnel_t * (1 + 1e-4)
        # At the Bragg line the cell below the face, filtered by the one above, holds less.
        assert ratio[~clear].min() < 0.98 * fresnel_t


def test_stored_light_is_a_density_not_a_sum_over_rays():
    # Four times the rays: the scattered fluence stays within the noise (a sum over rays
    # would grow fourfold); the direct light, solved per cell, does not change at all.
    few = opalray.light_pass(face_on(), light={"rays": 4096})
    many = opalray.light_pass(face_on(), light={"rays": 16384})
    scattered = [lp.fluence[:, 1:].sum() for lp in (few, many)]
    assert scattered[0] == pytest.approx(scattered[1], rel=0.1), scattered
    np.testing.assert_array_equal(few.fluence[:, 0], many.fluence[:, 0])
    assert many.ledger["rays"] > 3 * few.ledger["rays"]


def test_stone_domains_follow_the_diameter_law():
    # pinfire: thousands of grains; diameters D·(1 + spread·z), z standard normal clamped to
    # ±3, whose standard deviation is 0.98654 (the normal truncated at ±3σ).
    scene = opalray.Scene.preset("pinfire")
    stone = opalray.prepare(scene).stone
    d = stone.sphere_diameters_nm
    n = len(stone)
    mean_nm, spread = scene["crystal"]["sphere_diameter_nm"], scene["domains"]["sphere_diameter_spread"]
    assert n > 1000 and d.shape == (n,) and d.dtype == np.float32
    assert abs(d.mean() - mean_nm) < 4 * mean_nm * spread / np.sqrt(n)
    assert d.std() / mean_nm == pytest.approx(spread * 0.98654, abs=4 * spread / np.sqrt(2 * n))
    assert d.min() >= mean_nm * (1 - 3 * spread) - 1e-3 and d.max() <= mean_nm * (1 + 3 * spread) + 1e-3
    q = stone.orientations
    assert q.shape == (n, 4)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1, atol=1e-5)
    # One (111) normal: the quaternion (x, y, z, w) applied to (1, 1, 1)/√3, by hand.
    v = np.full(3, 1 / np.sqrt(3))
    u, w = q[:, :3], q[:, 3:]
    rotated = v + 2 * np.cross(u, np.cross(u, v) + w * v)
    np.testing.assert_allclose(stone.normals, rotated, atol=1e-5)


def test_stone_domain_ids_know_the_ellipsoid_and_the_potch():
    rng = np.random.default_rng(7)
    for name, potch in [("pinfire", None), ("paper", "void_ratio")]:
        # On the paper's ellipsoid, the domains throughout (no colour bar, no backing).
        scene = opalray.Scene.preset(name).replace(
            body={"cut": "ellipsoid", "colour_bar_mm": 0.0, "backing": "none"}
        )
        stages = opalray.prepare(scene)
        stone = stages.stone
        a = np.array(stone.semi_axes_mm)
        assert tuple(a) == tuple(scene["structure"]["semi_axes_mm"])
        points = rng.uniform(-1, 1, (200_000, 3)) * a
        ids = stone.domain_at(points)
        r = np.sqrt(((points / a) ** 2).sum(axis=1))
        far = np.abs(r - 1) > 1e-4
        np.testing.assert_array_equal(ids[far] == stone.OUTSIDE, r[far] > 1)
        inside = ids[r < 1]
        assert inside.min() >= stone.POTCH and inside.max() < len(stone)
        fraction = (inside == stone.POTCH).mean()
        if potch is None:
            # Grains are potch with probability domains.void_fraction (thousands of them).
            assert fraction == pytest.approx(scene["domains"]["void_fraction"], abs=0.015)
        else:
            # The paper's growth as balls leaves the potch the cell structure's voids are.
            assert fraction == pytest.approx(stages.structure.stats["void_ratio"], abs=0.01)
    # A slice: its shape, extent and the ids of its pixel centres.
    ids, extent = stone.slice("z", 0.0, pixels=(30, 40))
    assert ids.shape == (30, 40) and extent == (-a[0], a[0], -a[1], a[1])
    x = -a[0] + (np.arange(40) + 0.5) * 2 * a[0] / 40
    y = -a[1] + (np.arange(30) + 0.5) * 2 * a[1] / 30
    at = np.stack(np.broadcast_arrays(x[None, :], y[:, None], 0.0), axis=-1)
    np.testing.assert_array_equal(ids, stone.domain_at(at))
    with pytest.raises(ValueError, match="points_mm"):
        stone.domain_at(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="axis"):
        stone.slice("w")
