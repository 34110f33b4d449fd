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
    d = rs.drop(str(box_file), n=20, seed=7)
    expected = cli.json(["drop", str(box_file), "-n", "20", "--seed", "7"])
    assert d.to_dict() == expected
    assert d.drops == 20 and d.settled + d.unsettled == 20
    assert list(d.facets["count"]) == [f["count"] for f in expected["facets"]]
    assert int(d.facets["count"].sum()) == d.settled


def test_drop_parameters_map_to_the_cli_options(cli, box_file):
    d = rs.drop(box_file, 12, 3, certificate="none", height=1.0, restitution=0.4, friction=0.3)
    expected = cli.json(["drop", str(box_file), "-n", "12", "--seed", "3", "--certificate", "none",
                         "--height", "1", "--restitution", "0.4", "--friction", "0.3"])
    assert d.to_dict() == expected
    assert d.certified == 0


def test_flight_is_the_cli_flight_option(cli, box_file):
    d = rs.drop(box_file, 16, 4, flight="rapier")
    expected = cli.json(["drop", str(box_file), "-n", "16", "--seed", "4", "--flight", "rapier"])
    assert d.to_dict() == expected
    assert expected["params"]["flight"] == "rapier"
    default = rs.drop(box_file, 16, 4)
    assert default.to_dict()["params"]["flight"] == "free"
    fast = rs.drop(box_file, 16, 4, fast=True)
    assert fast.to_dict() == cli.json(["drop", str(box_file), "-n", "16", "--seed", "4", "--fast"])
    assert fast.to_dict()["params"]["dt"] == pytest.approx(1 / 120)


def test_presets_and_surfaces_are_the_cli_ones(cli, box_file):
    d = rs.drop(box_file, 10, 2, preset="drop", surface="stone-on-stone", size=0.05, spin=3.0)
    expected = cli.json(["drop", str(box_file), "-n", "10", "--seed", "2", "--preset", "drop",
                         "--surface", "stone-on-stone", "--size", "0.05", "--spin", "3"])
    assert d.to_dict() == expected
    assert expected["preset"] == "drop on stone-on-stone"


def test_drops_do_not_depend_on_threads_or_chunks(box_file):
    a = rs.analyze(box_file)
    one = rs.drop(a, 40, 11, threads=1)
    two = rs.drop(a, 40, 11, threads=2)
    assert one.to_dict() == two.to_dict()
    for k in one.outcomes:
        np.testing.assert_array_equal(one.outcomes[k], two.outcomes[k])
    # Drop i depends only on (seed, i): the first 10 of a longer run are a run of 10.
    ten = rs.drop(a, 10, 11)
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
    p = rs.perturb(box_file, equilibria=[0], trials=2, eps_steps=2, eps_min=1e-3, eps_max=0.5)
    expected = cli.json(["perturb", str(box_file), "--equilibrium", "0", "-n", "2", "--eps-steps", "2",
                         "--eps-min", "1e-3", "--eps-max", "0.5"])
    assert p.to_dict() == expected
    assert len(p.trials["epsilon"]) == 4


def test_shake_is_the_cli_report(cli, box_file):
    s = rs.shake(box_file, equilibria=[0], trials=2, pga_max=0.8, pga_steps=2)
    expected = cli.json(["shake", str(box_file), "--equilibrium", "0", "-n", "2", "--pga-max", "0.8",
                         "--pga-steps", "2"])
    assert s.to_dict() == expected
    assert len(s.trials["pga"]) == 4


def test_shake_rock_is_the_cli_run(cli, box_file, tmp_path):
    # One sine cycle of 0.4 g at 2 Hz along x, written by the test.
    t = np.arange(0, 1.0 + 1e-9, 0.005)
    a = np.where(t <= 0.5, 0.4 * np.sin(2 * np.pi * 2 * t), 0.0)
    rec = tmp_path / "pulse.csv"
    rec.write_text("time_s,ax_g\n" + "".join(f"{x:.3f},{y:.9f}\n" for x, y in zip(t, a)))
    args = ["--pose", "facet:0", "--length-unit", "cm", "--columns", "time_s,ax_g", "--azimuth", "30"]
    expected = cli.json(["shake", str(box_file), "--motion", str(rec), *args])
    r = rs.shake_rock(box_file, pose="facet:0", length_unit="cm", motion=rec, columns="time_s,ax_g", azimuth=30)
    assert r == expected
    assert set(r) >= {"overturned", "max_tilt_deg", "pga_g", "pgv_m_s", "slide_m"}
    # The same numbers as an array in m/s²: the same run (the CSV's interval is read from printed
    # times, so it may differ from 0.005 in the last bit: numbers agree to 1e-6, not bit for bit).
    values = np.array([float(f"{y:.9f}") for y in a]) * 9.81
    b = rs.shake_rock(box_file, pose="facet:0", length_unit=0.01, accel=values, dt=0.005, azimuth=30)
    assert b["record"] == "accel" and set(b) == set(r)
    for k, v in r.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            assert b[k] == v or k == "record", k
        else:
            assert b[k] == pytest.approx(v, rel=1e-6, abs=1e-9), k
    with pytest.raises(ValueError, match="not both"):
        rs.shake_rock(box_file, pose="facet:0", motion=rec, accel=values, dt=0.005)
    with pytest.raises(ValueError, match="pose"):
        rs.shake_rock(box_file, pose="upright", motion=rec)
