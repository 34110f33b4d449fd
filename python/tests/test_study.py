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
