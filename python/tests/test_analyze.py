"""The static analysis from Python against trimesh's mass properties and the CLI's JSON."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

import rocking_stones as rs
from conftest import mesh

MESHES = [
    "stone_quarry_ibois_E34_decimated500_bin.ply",
    "stone_quarry_ibois_A0_decimated500_bin.ply",
    "stone_quarry_ibois_stone0_ascii.ply",
    "moon_mars_deimos_thomas_bin.ply",
    "asteroid_25143_itokawa_radar_ostro2005_pdstab.obj",
]


@pytest.mark.parametrize("name", MESHES)
def test_mass_properties_match_trimesh(name):
    path = mesh(name)
    # As stored: trimesh's default processing merges vertices closer than 1e-8, which moves them.
    tm = trimesh.load(path, force="mesh", process=False)
    assert tm.is_watertight
    a = rs.analyze(tm)  # the very coordinates trimesh integrates
    scale = np.abs(tm.vertices).max()
    assert a.volume == pytest.approx(tm.volume, rel=1e-9)
    np.testing.assert_allclose(a.center_of_mass, tm.center_mass, rtol=0, atol=1e-9 * scale)
    inertia = tm.moment_inertia  # about the centre of mass, density 1
    np.testing.assert_allclose(a.inertia, inertia, rtol=0, atol=1e-9 * np.abs(inertia).max())
    assert a.area == pytest.approx(tm.area, rel=1e-9)
    # From the file: trimesh reads a PLY `float` property as float32, the library parses the
    # decimal text of an ASCII PLY in f64, so they agree to f32 precision there.
    assert rs.analyze(path).volume == pytest.approx(tm.volume, rel=1e-6)
    # From the file: trimesh reads a PLY `float` property as float32, the library parses the
    # decimal text of an ASCII PLY in f64, so they agree to f32 precision there.
    assert rs.analyze(path).volume == pytest.approx(tm.volume, rel=1e-6)


@pytest.mark.parametrize("name", MESHES)
def test_trimesh_object_gives_the_same_solid_as_the_file(name):
    path = mesh(name)
    from_file = rs.analyze(path)
    from_trimesh = rs.analyze(trimesh.load(path, force="mesh", process=False), name="tm")
    assert from_trimesh.name == "tm"
    assert from_trimesh.volume == pytest.approx(from_file.volume, rel=1e-6)
    np.testing.assert_allclose(from_trimesh.center_of_mass, from_file.center_of_mass, rtol=1e-6)
    # trimesh may reorder vertices and faces, not the hull or its equilibria.
    assert from_trimesh.micro == from_file.micro
    assert from_trimesh.macro == from_file.macro


@pytest.mark.parametrize("name", MESHES[:3] + [None])
def test_to_dict_is_the_cli_json(cli, name):
    args = ["analyze"] if name is None else ["analyze", str(mesh(name))]
    a = rs.analyze(None if name is None else str(mesh(name)))
    assert a.to_dict() == cli.json(args)
    # Byte for byte: the same serde value, pretty-printed the same way.
    assert a.to_json() + "\n" == cli.run([*args, "--json"]).stdout


def test_to_dict_with_nu_and_tolerance_is_the_cli_json(cli):
    path = str(mesh(MESHES[0]))
    a = rs.analyze(path, nu=0.0035, coplanar_tol=1e-6)
    assert a.nu_source == "user" and a.nu == 0.0035
    assert a.to_dict() == cli.json(["analyze", path, "--nu", "0.0035", "--coplanar-tol", "1e-6"])


def test_arrays_and_columns_agree_with_the_report():
    a = rs.analyze(mesh(MESHES[0]))
    d = a.to_dict()
    eq = a.equilibria
    n = len(d["equilibria"])
    assert all(len(col) == n for col in eq.values())
    assert a.points.shape == (n, 3)
    assert list(eq["kind"]) == [e["kind"] for e in d["equilibria"]]
    assert list(eq["site"]) == [e["site"]["on"] for e in d["equilibria"]]
    np.testing.assert_array_equal(eq["r"], [e["r"] for e in d["equilibria"]])
    S, U, H = a.micro
    assert (eq["kind"] == "stable").sum() == S and (eq["kind"] == "unstable").sum() == U
    assert S + U - H == 2
    st = a.staircase
    assert st["nu_lo"][0] == 0 and (st["stable"][0], st["unstable"][0], st["saddle"][0]) == a.micro
    assert a.counts_at(a.nu) == a.macro
    np.testing.assert_array_equal(st["nu_hi"], [s["nu_hi"] for s in d["staircase"]])
    assert len(a.rocking["index"]) == len(d["rocking"])
    assert set(a.rocking["flock_type"]) <= {"unstable", "saddle"}
    assert a.flocks == d["flocks"] and a.shape == d["shape"] and a.plateau == d["plateau"]
    assert a.hull["facets"] == a.facet_normals.shape[0]
    assert a.vertices.shape == (d["mesh"]["vertices"], 3) and a.faces.shape == (d["mesh"]["triangles"], 3)
    json.dumps(d)  # plain JSON types only


PLATONIC = {  # (F, V, E) = (S, U, H)
    "tetrahedron": (4, 4, 6),
    "cube": (6, 8, 12),
    "octahedron": (8, 6, 12),
    "dodecahedron": (12, 20, 30),
    "icosahedron": (20, 12, 30),
}


@pytest.mark.parametrize("shape", list(PLATONIC))
def test_platonic_solids_have_f_v_e_equilibria(shape):
    v, f = rs.generate(shape)
    a = rs.analyze((v, f))
    assert a.micro == PLATONIC[shape]
    assert a.hull["facets"] == PLATONIC[shape][0]
    # Rotated and scaled through trimesh: the same counts.
    tm = trimesh.Trimesh(v, f, process=False)
    tm.apply_transform(trimesh.transformations.random_rotation_matrix(np.random.default_rng(3).random(3)))
    tm.apply_scale(123.0)
    assert rs.analyze(tm).micro == PLATONIC[shape]


def test_trimesh_primitives():
    assert rs.analyze(trimesh.creation.icosahedron()).micro == (20, 12, 30)
    assert rs.analyze(trimesh.creation.box(extents=(3.0, 2.0, 1.0))).micro == (6, 8, 12)


def test_inward_mesh_is_flipped_and_duplicates_welded():
    v, f = rs.generate("cube")
    soup = v[f.reshape(-1)]  # three new vertices per triangle, as an STL stores them
    a = rs.analyze((soup, np.arange(len(soup)).reshape(-1, 3)[:, ::-1]))
    assert a.repairs["flipped"] and a.repairs["welded_vertices"] == len(soup) - 8
    assert a.micro == (6, 8, 12) and a.volume > 0
