"""Broken meshes and bad options raise Python exceptions carrying the CLI's messages."""

from __future__ import annotations

import numpy as np
import pytest

import rocking_stones as rs

TETRA_V = np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])
TETRA_F = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])


def write_ply(path, v, f):
    lines = ["ply", "format ascii 1.0", f"element vertex {len(v)}", "property double x",
             "property double y", "property double z", f"element face {len(f)}",
             "property list uchar int vertex_indices", "end_header"]
    lines += [" ".join(repr(float(x)) for x in p) for p in v]
    lines += ["3 " + " ".join(str(int(i)) for i in t) for t in f]
    path.write_text("\n".join(lines) + "\n")
    return path


BROKEN = {
    # Open where a face looks up: not an open scan standing on its base (one open at its bottom
    # is read, closed by a flat cap).
    "open_top": (TETRA_V, TETRA_F[[0, 1, 3]]),
    "misoriented": (TETRA_V, np.vstack([TETRA_F[:3], TETRA_F[3:, ::-1]])),
    "two_shells": (np.vstack([TETRA_V, TETRA_V + 5]), np.vstack([TETRA_F, TETRA_F + 4])),
    "flat": (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]), TETRA_F),
    "nan": (np.vstack([TETRA_V[:3], [[np.nan, 0, 0]]]), TETRA_F),
}


@pytest.mark.parametrize("kind", list(BROKEN))
def test_broken_mesh_raises_the_cli_message(cli, tmp_path, kind):
    v, f = BROKEN[kind]
    path = write_ply(tmp_path / f"{kind}.ply", v, f)
    expected = cli.error(["analyze", str(path)])
    assert str(path) in expected
    with pytest.raises(rs.MeshError) as e:
        rs.analyze(path)
    assert str(e.value) == expected
    if kind != "nan":  # the PLY reader refuses NaN itself; in memory the mesh check does
        # The same arrays in memory, named like the file: the same message.
        with pytest.raises(rs.MeshError) as e:
            rs.analyze((v, f), name=str(path))
        assert str(e.value) == expected
    with pytest.raises(ValueError, match="<memory>"):
        rs.analyze((v, f))


def test_mesh_error_is_a_value_error():
    assert issubclass(rs.MeshError, ValueError)


def test_missing_file_is_file_not_found(cli, tmp_path):
    path = tmp_path / "missing.ply"
    with pytest.raises(FileNotFoundError) as e:
        rs.analyze(path)
    assert str(e.value) == cli.error(["analyze", str(path)])


def test_truncated_file(cli, tmp_path):
    path = tmp_path / "cut.stl"
    path.write_bytes(b"\0" * 80 + (10).to_bytes(4, "little") + b"\0" * 60)
    with pytest.raises(rs.MeshError) as e:
        rs.analyze(path)
    assert str(e.value) == cli.error(["analyze", str(path)])


def test_bad_nu_has_the_library_message():
    v, f = rs.generate("cube")
    with pytest.raises(ValueError, match=r"nu must be in \(0, 1\], got 2"):
        rs.analyze((v, f), nu=2.0)


def test_bad_inputs():
    v, f = rs.generate("cube")
    with pytest.raises(TypeError, match="mesh must be a path"):
        rs.analyze(42)
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        rs.analyze((v[:, :2], f))
    with pytest.raises(TypeError, match="integer"):
        rs.analyze((v, f.astype(float)))
    with pytest.raises(rs.MeshError, match="vertex -1"):
        rs.analyze((v, np.where(f == 0, -1, f)))
    with pytest.raises(rs.MeshError, match="only 8 vertices"):
        rs.analyze((v, np.where(f == 0, 99, f)))


def test_bad_drop_parameters():
    box = rs.generate("box")
    with pytest.raises(TypeError, match="unknown parameter \"bounce\""):
        rs.drop(box, 1, size=0.01, bounce=1.0)
    with pytest.raises(ValueError, match="restitution must be in"):
        rs.drop(box, 1, size=0.01, restitution=2.0)
    with pytest.raises(ValueError, match="preset"):
        rs.drop(box, 1, size=0.01, preset="gravel")
    with pytest.raises(ValueError, match="size"):
        rs.drop(box, 1, size=-1.0)
    with pytest.raises(ValueError, match="length_unit= .*or size="):
        rs.drop(box, 1)
    with pytest.raises(ValueError, match="contact model"):
        rs.perturb(box, size=0.01, contact_model="gravel")
    with pytest.raises(ValueError, match="certificate must be one of"):
        rs.drop(box, 1, size=0.01, certificate="maybe")


def test_a_dynamic_study_asks_for_the_scans_unit_only(tmp_path):
    # study() has no size=: a folder of scans of many sizes is sized by its unit alone.
    import trimesh

    v, f = rs.generate("pebble", n=300, seed=1)
    trimesh.Trimesh(v, f, process=False).export(tmp_path / "p.ply")
    with pytest.raises(ValueError, match=r"give length_unit= \(mm, cm, m, km, in or metres per mesh unit\)$"):
        rs.study(tmp_path, dynamic=True)
