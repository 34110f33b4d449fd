"""Open scans (a rock scanned standing on its pedestal, open where it meets it) from Python:
a trimesh mesh, (vertices, faces) and the file read alike, checked against trimesh and the CLI."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

import rocking_stones as rs
from conftest import REPO

OPEN_SCAN = REPO / "data" / "open_scan_E34.ply"


def test_an_open_trimesh_mesh_is_read_as_the_file_and_the_cli_read_it(cli):
    tm = trimesh.load(OPEN_SCAN, force="mesh", process=False)
    assert not tm.is_watertight
    from_mesh = rs.analyze(tm)
    from_arrays = rs.analyze((tm.vertices, tm.faces))
    from_file = rs.analyze(OPEN_SCAN)
    o = from_mesh.open_scan
    assert o is not None and o["base"] == "flat cap"
    assert from_arrays.to_dict() == from_mesh.to_dict()
    # The file's report is the CLI's, byte for byte.
    assert from_file.to_dict() == cli.json(["analyze", str(OPEN_SCAN)])
    assert from_file.open_scan == o
    # The rim against trimesh: its boundary (the edges of one face) is as long as the rim, and
    # the solid closed by the flat cap is the scan's triangles plus the cap.
    boundary = trimesh.grouping.group_rows(tm.edges_sorted, require_count=1)
    edges = tm.vertices[tm.edges_sorted[boundary]]
    length = np.linalg.norm(edges[:, 0] - edges[:, 1], axis=1).sum()
    assert o["rim"]["perimeter"] == pytest.approx(length, rel=1e-12)
    assert o["rim"]["centre"][2] == pytest.approx(5.0, abs=1e-9)
    marked = [e for e in from_mesh.to_dict()["equilibria"] if e.get("hidden_base")]
    counts = o["on_hidden_base"]
    assert len(marked) == counts["stable"] + counts["unstable"] + counts["saddle"] > 0


def test_a_closed_stone_has_no_open_scan_and_an_open_top_is_refused():
    assert rs.analyze(None).open_scan is None
    box = trimesh.creation.box(extents=(2.0, 1.5, 1.0))
    top = box.face_normals[:, 2] > 0.9
    bowl = trimesh.Trimesh(box.vertices, box.faces[~top], process=False)
    with pytest.raises(rs.MeshError, match="not at the bottom of the scan"):
        rs.analyze(bowl, name="bowl")
    # Without its bottom it stands as a field scan: the flat cap gives the box back.
    bottom = box.face_normals[:, 2] < -0.9
    standing = rs.analyze(trimesh.Trimesh(box.vertices, box.faces[~bottom], process=False))
    assert standing.volume == pytest.approx(3.0, rel=1e-12)
    assert standing.micro == (6, 8, 12)
    assert standing.open_scan["rim"]["area"] == pytest.approx(3.0, rel=1e-12)
