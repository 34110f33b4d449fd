"""rocking_stones.study against `rocking study`."""

from __future__ import annotations

import trimesh

import rocking_stones as rs


def test_study_rows_are_the_cli_pebbles_csv(cli, tmp_path):
    folder = tmp_path / "scans"
    folder.mkdir()
    for i, shape in enumerate(["pebble", "ellipsoid"]):
        v, f = rs.generate(shape, n=300, seed=i)
        trimesh.Trimesh(v, f, process=False).export(folder / f"p{i}.ply")
    (folder / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "meta.csv").write_text("id;sample;site\np0;A;beach\np1;A;river\nbroken;B;quarry\n")
    s = rs.study(folder, tmp_path / "meta.csv")
    out = tmp_path / "out"
    cli.run(["study", str(folder), "--meta", str(tmp_path / "meta.csv"), "-o", str(out)])
    assert s.pebbles_csv() == (out / "pebbles.csv").read_text()
    assert s.samples_csv() == (out / "samples.csv").read_text()
    assert len(s) == 3 and [r["id"] for r in s.rows] == ["broken", "p0", "p1"]
    row = s.rows[1]
    assert row["sample"] == "A" and row["site"] == "beach" and row["error"] is None
    assert isinstance(row["micro_S"], int) and isinstance(row["volume"], float)
    assert s.errors[0] is not None and "open" in s.errors[0] and s.reports[0] is None
    assert s.reports[1]["micro"]["stable"] == row["micro_S"]
    cols = s.to_dict()
    assert list(cols["id"]) == ["broken", "p0", "p1"]


def test_the_dynamic_study_needs_the_size_it_sets_pebbles_down_at(cli, tmp_path):
    import warnings

    import pytest

    folder = tmp_path / "scans"
    folder.mkdir()
    v, f = rs.generate("pebble", n=300, seed=1)
    trimesh.Trimesh(v, f, process=False).export(folder / "p.ply")
    with pytest.raises(ValueError, match=r"\(the scans\): its length unit is not known"):
        rs.study(folder, dynamic=True, trials=2)
    out = tmp_path / "out"
    # Given in km, the unit pebble is a kilometre: said; in cm, nothing to say, and the CLI's rows.
    with pytest.warns(UserWarning, match="outside the plausible sizes"):
        rs.study(folder, dynamic=True, trials=2, length_unit="km")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cm = rs.study(folder, dynamic=True, trials=2, length_unit="cm")
    cli.run(["study", str(folder), "--dynamic", "--trials", "2", "--length-unit", "cm", "-o", str(out)])
    assert cm.pebbles_csv() == (out / "pebbles.csv").read_text()
    with pytest.raises(ValueError, match="dynamic=True"):
        rs.study(folder, length_unit="cm")


def test_the_hand_experimenter_gives_each_pebble_a_distribution_as_the_cli(cli, tmp_path):
    import pytest

    folder = tmp_path / "scans"
    folder.mkdir()
    for i in range(3):
        v, f = rs.generate("pebble", n=800, roughness=0.3, seed=i)
        trimesh.Trimesh(v, f, process=False).export(folder / f"p{i}.ply")
    s = rs.study(folder)
    out = tmp_path / "out"
    cli.run(["study", str(folder), "-o", str(out)])
    assert s.pebbles_csv() == (out / "pebbles.csv").read_text()
    assert s.hand_json() == (out / "hand.json").read_text()
    assert s.nu is None and s.experimenter["stable"]["median"] < s.experimenter["unstable"]["median"]
    hand = s.hand()
    for row, peb in zip(s.rows, hand["pebbles"]):
        d = peb["distribution"]
        ps = {w["count"]: w["p"] for w in d["stable"]}
        pu = {w["count"]: w["p"] for w in d["unstable"]}
        assert abs(sum(ps.values()) - 1) < 1e-9 and abs(sum(pu.values()) - 1) < 1e-9
        # The most likely pair is the pair of the most likely counts; H by Poincaré–Hopf.
        best_s, best_u = max(ps, key=ps.get), max(pu, key=pu.get)
        assert (row["hand_S"], row["hand_U"], row["hand_H"]) == (best_s, best_u, best_s + best_u - 2)
        assert abs(row["hand_p"] - ps[best_s] * pu[best_u]) < 1e-4
        assert row["hand_pairs"].startswith(f"{best_s}:{best_u}:")
    # Given tolerances: a fixed pair of ν (no spread) is certain and is G(ν) of each count.
    fixed = rs.study(folder, tolerances=(0.0035, 0.0, 0.0035, 0.0))
    one = rs.study(folder, nu=0.0035)
    assert one.nu == 0.0035 and one.experimenter is None and "hand_nu" in one.rows[0]
    for a, b in zip(fixed.rows, one.rows):
        assert (a["hand_S"], a["hand_U"], a["hand_H"], a["hand_p"]) == (b["hand_S"], b["hand_U"], b["hand_H"], 1.0)
    with pytest.raises(ValueError, match="not both"):
        rs.study(folder, nu=0.0035, tolerances=(0.0035, 0.0, 0.0035, 0.0))
    with pytest.raises(ValueError, match="stable_spread"):
        rs.study(folder, tolerances=(0.0035, -1.0, 0.0035, 0.0))
