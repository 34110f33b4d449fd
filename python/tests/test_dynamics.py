"""Drops, basins, perturbations and shaking from Python against the CLI."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

import rocking_stones as rs


@pytest.fixture(scope="module")
def box_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("box") / "box.ply"
    v, f = rs.generate("box", axes=(1.0, 0.8, 0.5))
    trimesh.Trimesh(v, f, process=False).export(path, encoding="ascii")
    return path


def test_drop_with_a_seed_gives_the_cli_counts(cli, box_file):
    d = rs.drop(str(box_file), n=20, seed=7, size=0.01)
    expected = cli.json(["drop", str(box_file), "-n", "20", "--seed", "7", "--size", "0.01"])
    assert d.to_dict() == expected
    assert d.drops == 20 and d.settled + d.unsettled == 20
    assert list(d.facets["count"]) == [f["count"] for f in expected["facets"]]
    assert int(d.facets["count"].sum()) == d.settled
    # the columns facets and flocks share are those of the JSON, row by row
    for table, rows in ((d.facets, expected["facets"]), (d.flocks, expected["flocks"])):
        assert list(table["fraction"]) == [r["fraction"] for r in rows]
        assert [list(r["ci95"]) for r in rows] == [[lo, hi] for lo, hi in zip(table["ci95_lo"], table["ci95_hi"])]
        assert list(table["static_probability"]) == [r["static_probability"] for r in rows]
    # The run's depth is the deepest of its drops', measured after every step and sub-step.
    assert d.deepest_penetration == float(d.outcomes["deepest_penetration"].max())
    assert 0.0 < d.deepest_penetration < 0.02


def test_drop_parameters_map_to_the_cli_options(cli, box_file):
    d = rs.drop(box_file, 12, 3, certificate="none", height=1.0, restitution=0.4, friction=0.3, size=0.01,
                dt=0.0005, spin=200.0, rolling_resistance_mm=0.1)
    expected = cli.json(["drop", str(box_file), "-n", "12", "--seed", "3", "--certificate", "none",
                         "--height", "1", "--restitution", "0.4", "--friction", "0.3", "--size", "0.01",
                         "--dt", "0.0005", "--spin", "200", "--rolling-resistance-mm", "0.1"])
    assert d.to_dict() == expected
    assert d.certified == 0
    # Times, spins and lengths in real units for R_max = 1 cm: 0.5 ms is 0.005 s of the scaled body,
    # 200 rad/s is 20 rad/s of it, δ = 0.1 mm is 0.01 R_max.
    p = expected["params"]
    assert (p["dt"], p["spin"], p["rolling_resistance"]) == pytest.approx((0.005, 20.0, 0.01), rel=1e-12)
    with pytest.raises(TypeError, match="rolling_resistance_mm"):
        rs.drop(box_file, 1, size=0.01, rolling_resistance=0.02)


def test_flight_is_the_cli_flight_option(cli, box_file):
    d = rs.drop(box_file, 16, 4, flight="rapier", size=0.01)
    expected = cli.json(["drop", str(box_file), "-n", "16", "--seed", "4", "--flight", "rapier", "--size", "0.01"])
    assert d.to_dict() == expected
    assert expected["params"]["flight"] == "rapier"
    default = rs.drop(box_file, 16, 4, size=0.01)
    assert default.to_dict()["params"]["flight"] == "free"
    assert default.to_dict()["params"]["dt"] == pytest.approx(1 / 120)
    assert rs.drop(box_file, 16, 4, fast=True, size=0.01).to_dict() == default.to_dict()
    reference = rs.drop(box_file, 16, 4, reference=True, size=0.01)
    assert reference.to_dict() == cli.json(["drop", str(box_file), "-n", "16", "--seed", "4", "--reference",
                                            "--size", "0.01"])
    assert reference.to_dict()["params"]["dt"] == pytest.approx(1 / 240)
    with pytest.raises(ValueError, match="exclude each other"):
        rs.drop(box_file, 4, 4, reference=True, fast=True, size=0.01)


def test_presets_and_surfaces_are_the_cli_ones(cli, box_file):
    d = rs.drop(box_file, 10, 2, preset="drop", surface="stone-on-stone", size=0.05, spin=3.0)
    expected = cli.json(["drop", str(box_file), "-n", "10", "--seed", "2", "--preset", "drop",
                         "--surface", "stone-on-stone", "--size", "0.05", "--spin", "3"])
    assert d.to_dict() == expected
    assert expected["preset"] == "drop on stone-on-stone"


def test_drops_do_not_depend_on_threads_or_chunks(box_file):
    a = rs.analyze(box_file)
    one = rs.drop(a, 40, 11, threads=1, size=0.01)
    two = rs.drop(a, 40, 11, threads=2, size=0.01)
    assert one.to_dict() == two.to_dict()
    for k in one.outcomes:
        np.testing.assert_array_equal(one.outcomes[k], two.outcomes[k])
    # Drop i depends only on (seed, i): the first 10 of a longer run are a run of 10.
    ten = rs.drop(a, 10, 11, size=0.01)
    np.testing.assert_array_equal(ten.outcomes["facet"], one.outcomes["facet"][:10])


def test_basins_of_symmetric_solids():
    cube = rs.basins(rs.generate("cube"))
    assert len(cube) == 6
    np.testing.assert_allclose(cube.probability, 1 / 6, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(cube.normal, axis=1), 1.0)
    tetra = rs.analyze(rs.generate("tetrahedron")).basins()
    np.testing.assert_allclose(tetra.probability, 0.25, atol=1e-12)
    assert tetra.probability.sum() == pytest.approx(1.0, abs=1e-12)


def test_basins_of_a_box_favour_the_large_faces(box_file):
    b = rs.basins(box_file)
    cols = b.to_dict()
    # The two faces normal to the short axis (z) are the most likely.
    big = np.abs(cols["nz"]) > 0.99
    assert big.sum() == 2 and cols["probability"][big].min() > cols["probability"][~big].max()
    assert b.flock_probability.sum() == pytest.approx(1.0, abs=1e-12)


def test_perturb_is_the_cli_report(cli, box_file):
    p = rs.perturb(box_file, equilibria=[0], trials=2, eps_steps=2, eps_min=1e-3, eps_max=0.5, length_unit="m",
                   certificate="flock", max_time=10.0)
    expected = cli.json(["perturb", str(box_file), "--equilibrium", "0", "-n", "2", "--eps-steps", "2",
                         "--eps-min", "1e-3", "--eps-max", "0.5", "--length-unit", "m", "--certificate", "flock",
                         "--max-time", "10"])
    assert p.to_dict() == expected
    with pytest.raises(ValueError, match="contact_model"):
        rs.perturb(box_file, length_unit="m", preset="damped")
    assert len(p.trials["epsilon"]) == 4


def test_shake_is_the_cli_report(cli, box_file):
    s = rs.shake(box_file, equilibria=[0], trials=2, pga_max=0.8, pga_steps=2, length_unit="m",
                 contact_model="damped")
    expected = cli.json(["shake", str(box_file), "--equilibrium", "0", "-n", "2", "--pga-max", "0.8",
                         "--pga-steps", "2", "--length-unit", "m", "--contact-model", "damped"])
    assert s.to_dict() == expected
    assert len(s.trials["pga"]) == 4


def test_shake_rock_is_the_cli_run(cli, box_file, tmp_path):
    # One sine cycle of 0.4 g at 2 Hz along x, written by the test.
    t = np.arange(0, 1.0 + 1e-9, 0.005)
    a = np.where(t <= 0.5, 0.4 * np.sin(2 * np.pi * 2 * t), 0.0)
    rec = tmp_path / "pulse.csv"
    rec.write_text("time_s,ax_g\n" + "".join(f"{x:.3f},{y:.9f}\n" for x, y in zip(t, a)))
    args = ["--pose", "equilibrium:0", "--length-unit", "cm", "--columns", "time_s,ax_g", "--azimuth", "30"]
    expected = cli.json(["shake", str(box_file), "--motion", str(rec), *args])
    r = rs.shake_rock(box_file, pose="equilibrium:0", length_unit="cm", motion=rec, columns="time_s,ax_g", azimuth=30)
    assert r == expected
    assert set(r) >= {"overturned", "max_tilt_deg", "pga_g", "pgv_m_s", "slide_m"}
    # The same numbers as an array in m/s²: the same run (the CSV's interval is read from printed
    # times, so it may differ from 0.005 in the last bit: numbers agree to 1e-6, not bit for bit).
    values = np.array([float(f"{y:.9f}") for y in a]) * 9.81
    b = rs.shake_rock(box_file, pose="equilibrium:0", length_unit=0.01, accel=values, dt=0.005, azimuth=30)
    assert b["record"] == "accel" and set(b) == set(r)
    for k, v in r.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            assert b[k] == v or k == "record", k
        else:
            assert b[k] == pytest.approx(v, rel=1e-6, abs=1e-9), k
    with pytest.raises(ValueError, match="not both"):
        rs.shake_rock(box_file, pose="equilibrium:0", motion=rec, accel=values, dt=0.005)
    with pytest.raises(ValueError, match="pose"):
        rs.shake_rock(box_file, pose="upright", motion=rec)


# Ensembles of a field rock: the 1 cm box (tips at 0.5 g) under 2 cycles at 2 Hz.
ROCK = dict(pose="equilibrium:0", length_unit="cm", columns="time_s,ax_g")


def pulse_csv(path, amplitude=0.7):
    """Two sine cycles of `amplitude` g at 2 Hz along x, then 1 s of rest, as a CSV."""
    t = np.arange(0, 2.0 + 1e-9, 0.005)
    a = np.where(t <= 1.0, amplitude * np.sin(2 * np.pi * 2 * t), 0.0)
    path.write_text("time_s,ax_g\n" + "".join(f"{x:.3f},{y:.9f}\n" for x, y in zip(t, a)))
    return path


def test_shake_rock_ensemble_is_the_cli_ensemble(cli, box_file, tmp_path):
    rec = pulse_csv(tmp_path / "pulse.csv")
    base = ["shake", str(box_file), "--pose", "equilibrium:0", "--length-unit", "cm", "--motion", str(rec),
            "--columns", "time_s,ax_g"]
    expected = cli.json([*base, "--ensemble", "2", "--seed", "3", "--contact-tolerance-mm", "0.01"])
    r = rs.shake_rock(box_file, motion=rec, ensemble=2, seed=3, uncertainty={"contact_tolerance_mm": 0.01}, **ROCK)
    assert r == expected
    assert r["probability"]["members"] == 2 and r["uncertainty"]["contact_tolerance_m"][0] == 0.0
    # Every key against its option (δ in mm on both sides).
    expected = cli.json([*base, "--ensemble", "3", "--seed", "4", "--contact-tolerance-mm", "0.005,0.02",
                         "--azimuth-range", "10,80", "--random-sign", "--friction-range", "0.4,0.6",
                         "--restitution-range", "0.1,0.3", "--rolling-resistance-range", "0.05,0.1",
                         "--surface", "rock-on-steel", "--scales", "1.5"])
    u = {"contact_tolerance_mm": (0.005, 0.02), "azimuth": (10, 80), "random_sign": True, "friction": [0.4, 0.6],
         "restitution": (0.1, 0.3), "rolling_resistance_mm": (0.05, 0.1)}
    r = rs.shake_rock(box_file, motion=rec, ensemble=3, seed=4, uncertainty=u, surface="rock-on-steel", scale=1.5,
                      **ROCK)
    assert r == expected
    assert r["uncertainty"]["rolling_resistance_m"] == pytest.approx([0.05e-3, 0.1e-3], rel=1e-12)


def test_shake_rock_ensemble_draws_depend_only_on_the_seed(box_file, tmp_path):
    rec = pulse_csv(tmp_path / "pulse.csv")
    u = {"friction": (0.5, 0.6), "restitution": (0.2, 0.3), "rolling_resistance_mm": (0.05, 0.1)}
    a = rs.shake_rock(box_file, motion=rec, ensemble=2, seed=5, uncertainty=u, **ROCK)
    assert rs.shake_rock(box_file, motion=rec, ensemble=2, seed=5, uncertainty=u, **ROCK) == a
    c = rs.shake_rock(box_file, motion=rec, ensemble=2, seed=6, uncertainty=u, **ROCK)
    assert c["seed"] == 6 and a["seed"] == 5
    assert [m["draw"]["friction"] for m in c["members"]] != [m["draw"]["friction"] for m in a["members"]]
    # Member m is the same possible rock in a smaller ensemble (common random numbers).
    one = rs.shake_rock(box_file, motion=rec, ensemble=1, seed=5, uncertainty=u, **ROCK)
    assert one["members"] == a["members"][:1]
    # Nothing stated: the contact ranges over the surface pair's ranges, as with an empty dict.
    none = rs.shake_rock(box_file, motion=rec, ensemble=1, **ROCK)
    assert none == rs.shake_rock(box_file, motion=rec, ensemble=1, uncertainty={}, **ROCK)
    assert none["uncertainty"]["friction"] is not None and none["uncertainty"]["azimuth_deg"] is None
    # Without ensemble=: the single run, as before.
    assert "probability" not in rs.shake_rock(box_file, motion=rec, seed=5, **ROCK)


def test_shake_rock_ensemble_dict(box_file, tmp_path):
    rec = pulse_csv(tmp_path / "pulse.csv")
    u = {"contact_tolerance_mm": (0.005, 0.02), "azimuth": "unknown", "random_sign": True, "friction": (0.4, 0.6),
         "restitution": (0.1, 0.3), "rolling_resistance_mm": (0.05, 0.1)}
    r = rs.shake_rock(box_file, motion=rec, ensemble=8, seed=2, uncertainty=u, **ROCK)
    assert set(r) >= {"record", "scale", "pga_g", "seed", "uncertainty", "probability", "sensitivity", "tipping",
                      "members"}
    p = r["probability"]
    assert set(p) == {"members", "settled", "overturned", "p_overturn", "interval95"}
    assert p["members"] == 8 == len(r["members"])
    assert 0 <= p["overturned"] <= p["settled"] <= 8
    assert 0 <= p["p_overturn"] <= 1
    lo, hi = p["interval95"]
    assert 0 <= lo <= p["p_overturn"] <= hi <= 1
    assert p["p_overturn"] == sum(m["run"]["settled"] and m["run"]["overturned"] for m in r["members"]) / p["settled"]
    tol = r["uncertainty"]["contact_tolerance_m"]
    assert tol == pytest.approx([0.005e-3, 0.02e-3], rel=1e-12)
    assert r["uncertainty"]["azimuth_deg"] == [0.0, 360.0]
    for k, m in enumerate(r["members"]):
        assert set(m) == {"draw", "run"}
        d = m["draw"]
        assert d["member"] == k
        assert tol[0] <= d["contact_tolerance_m"] <= tol[1]
        assert 0 <= d["azimuth_deg"] <= 360 and d["sign"] in (1.0, -1.0)
        assert 0.4 <= d["friction"] <= 0.6 and 0.1 <= d["restitution"] <= 0.3
        assert 0.05e-3 * (1 - 1e-12) <= d["rolling_resistance_m"] <= 0.1e-3 * (1 + 1e-12)
        assert m["run"]["azimuth_deg"] == pytest.approx(d["azimuth_deg"], abs=1e-9)
        # Every member stands on its own drawn base (the default): its rocking points' tan α.
        assert d["base"]["tan_alpha"] > 0 and len(d["base"]["support_m"]) == 3
    sens = {s["input"]: s for s in r["sensitivity"]}
    assert set(sens) == {"contact_tolerance", "azimuth", "sign", "friction", "restitution", "rolling_resistance",
                         "base_tan_alpha", "base_depth"}
    assert r["base"]["members"] == 8
    assert all(set(s) == {"input", "measure", "correlation"} for s in r["sensitivity"])
    assert sens["azimuth"]["measure"] == "circular-linear"
    assert all(s["measure"] == "spearman" for k, s in sens.items() if k != "azimuth")
    for k, s in sens.items():
        c = s["correlation"]
        assert c is None or (0 <= c <= 1 if k == "azimuth" else -1 <= c <= 1)
    # The quasi-static polar at tolerance 0 and at both ends of the range.
    assert [t["tolerance_m"] for t in r["tipping"]] == [0.0, *tol]
    # The scan's own base in every member: no base drawn, none ranked.
    scanned = rs.shake_rock(box_file, motion=rec, ensemble=2, uncertainty={"base": "scanned"}, **ROCK)
    assert "base" not in scanned and all("base" not in m["draw"] for m in scanned["members"])
    assert not {"base_tan_alpha", "base_depth"} & {s["input"] for s in scanned["sensitivity"]}
    # A known azimuth range is ranked like the rest.
    r = rs.shake_rock(box_file, motion=rec, ensemble=3, uncertainty={"azimuth": (0, 90)}, **ROCK)
    assert {s["input"]: s["measure"] for s in r["sensitivity"]}["azimuth"] == "spearman"
    assert all(0 <= m["draw"]["azimuth_deg"] <= 90 for m in r["members"])


def test_shake_rock_ensemble_bad_input(box_file, tmp_path):
    rec = pulse_csv(tmp_path / "pulse.csv")

    def shake(**kw):
        return rs.shake_rock(box_file, motion=rec, **ROCK, **kw)

    with pytest.raises(ValueError, match="frction") as e:
        shake(ensemble=2, uncertainty={"frction": (0.1, 0.2)})
    assert "rolling_resistance_mm" in str(e.value)  # the valid keys are listed
    with pytest.raises(ValueError, match="restitution"):
        shake(ensemble=2, uncertainty={"restitution": (0.2, 1.5)})
    with pytest.raises(ValueError, match="rolling_resistance_mm"):
        shake(ensemble=2, uncertainty={"rolling_resistance_mm": (0.2, 0.1)})
    with pytest.raises(ValueError, match="contact_tolerance_mm"):
        shake(ensemble=2, uncertainty={"contact_tolerance_mm": -0.001})
    with pytest.raises(ValueError, match="is now"):
        shake(ensemble=2, uncertainty={"contact_tolerance": 0.001})
    with pytest.raises(ValueError, match="friction"):
        shake(ensemble=2, uncertainty={"friction": (0.1, 0.2, 0.3)})
    with pytest.raises(ValueError, match="friction"):
        shake(ensemble=2, uncertainty={"friction": "0.1,0.2"})
    with pytest.raises(ValueError, match="azimuth"):
        shake(ensemble=2, uncertainty={"azimuth": "north"})
    with pytest.raises(ValueError, match="random_sign"):
        shake(ensemble=2, uncertainty={"random_sign": "yes"})
    with pytest.raises(ValueError, match="ensemble="):
        shake(uncertainty={"friction": (0.1, 0.2)})
    with pytest.raises(ValueError, match="not both"):
        shake(ensemble=2, azimuth=30, uncertainty={"azimuth": "unknown"})
    with pytest.raises(ValueError, match="ensemble"):
        shake(ensemble=0)


def test_a_mesh_without_a_size_is_refused_as_the_cli_refuses_it(cli, tmp_path):
    import warnings
    from pathlib import Path

    # A byte-identical copy of the bundled stone under another name: its unit is not known.
    copy = tmp_path / "mystone.ply"
    copy.write_bytes((Path(__file__).resolve().parents[2] / "data" / "default_pebble.ply").read_bytes())
    rec = pulse_csv(tmp_path / "pulse.csv", amplitude=0.3)
    rock = dict(pose="equilibrium:3", motion=rec, columns="time_s,ax_g")
    for run in (lambda: rs.drop(copy, 1), lambda: rs.perturb(copy, equilibria=[3], trials=1, eps_steps=1),
                lambda: rs.shake(copy, trials=1, pga_steps=1), lambda: rs.shake_rock(copy, **rock)):
        with pytest.raises(ValueError, match="mystone.ply: its length unit is not known.*give length_unit= "
                                             r"\(mm, cm, m, km, in or metres per mesh unit\) or size="):
            run()
    # In metres: run, and told that 178 m is not a stone's size.
    with pytest.warns(UserWarning, match="R_max = 178.3 m is outside the plausible sizes"):
        r = rs.shake_rock(copy, length_unit="m", **rock)
    assert r["size_assumed"] is False and r["r_max_m"] == pytest.approx(178.323, abs=1e-3)
    # In millimetres, and the bundled stone itself: nothing to say, and the same run, by either
    # pose: the equilibrium's index or the hull facet it rests on.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mm = rs.shake_rock(copy, length_unit="mm", **rock)
        bundled = rs.shake_rock(**rock)
        facet = rs.shake_rock(**{**rock, "pose": "facet:200"})
    assert mm == bundled == facet and mm["size_assumed"] is False
    assert mm == cli.json(["shake", str(copy), "--length-unit", "mm", "--pose", "equilibrium:3", "--motion", str(rec),
                           "--columns", "time_s,ax_g"])
