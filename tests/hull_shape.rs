//! `HullShape`, the hull as a parry3d collider: exact support points by hill climbing, the
//! project's own facets as support features, O(1) bounds, parry's dispatcher producing contacts
//! against a half-space and a cuboid ground, and rapier drops that agree with a cuboid collider.

use parry3d::math::{Pose, Real, Rotation, Vector};
use parry3d::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher, PointQuery, Ray, RayCast};
use parry3d::shape::{
    ConvexPolyhedron, Cuboid, FeatureId, HalfSpace, PackedFeatureId, PolygonalFeature, PolygonalFeatureMap, Shape,
    ShapeType, SupportMap, TypedShape,
};
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;
use rand_xoshiro::Xoshiro256PlusPlus;
use rapier3d::prelude::{
    CCDSolver, ColliderBuilder, ColliderSet, DefaultBroadPhase, ImpulseJointSet, IntegrationParameters, IslandManager,
    MultibodyJointSet, NarrowPhase, PhysicsPipeline, RigidBodyBuilder, RigidBodyHandle, RigidBodySet, SharedShape,
    SoftBodySet,
};
use rocking_stones::dynamics::engine::hull_shape::{HullShape, DEFAULT_FEATURE_ANGLE};
use rocking_stones::generate::{self, Platonic};
use rocking_stones::hull::{Polyhedron, DEFAULT_COPLANAR_TOL};
use rocking_stones::solid::MassProperties;
use rocking_stones::{Point3, Vec3};
use std::collections::BTreeSet;

fn dot64(p: Vector, d: Vector) -> f64 {
    p.x as f64 * d.x as f64 + p.y as f64 * d.y as f64 + p.z as f64 * d.z as f64
}

fn random_unit(rng: &mut Xoshiro256PlusPlus) -> Vector {
    loop {
        let mut g = || rng.sample::<f64, _>(StandardNormal) as Real;
        let v = Vector::new(g(), g(), g());
        if v.length() > 1e-3 {
            return v.normalize();
        }
    }
}

fn to_vector(v: &Vec3) -> Vector {
    Vector::new(v.x as Real, v.y as Real, v.z as Real)
}

/// The 2000-corner pebble of the brief: hull, G and the shape about G.
fn pebble() -> (Polyhedron, Point3, HullShape) {
    let mesh = generate::pebble([1.0, 0.7, 0.5], 0.02, 3000, 1);
    let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL).unwrap();
    let g = MassProperties::of(&mesh).unwrap().center_of_mass;
    let shape = HullShape::new(&poly, &g, 1.0);
    (poly, g, shape)
}

fn shape_of(mesh: &rocking_stones::mesh::TriMesh) -> (Polyhedron, HullShape) {
    let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL).unwrap();
    let g = MassProperties::of(mesh).unwrap().center_of_mass;
    let shape = HullShape::new(&poly, &g, 1.0);
    (poly, shape)
}

/// A right prism over a regular k-gon of circumradius 1 (caps have k corners), height 2h.
fn prism(k: usize, h: f64) -> Polyhedron {
    let pts: Vec<Point3> = (0..k)
        .flat_map(|i| {
            let t = 2.0 * std::f64::consts::PI * i as f64 / k as f64;
            [Point3::new(t.cos(), t.sin(), -h), Point3::new(t.cos(), t.sin(), h)]
        })
        .collect();
    Polyhedron::new(&pts, DEFAULT_COPLANAR_TOL).unwrap()
}

fn feature(shape: &HullShape, d: Vector) -> PolygonalFeature {
    let mut f = PolygonalFeature::default();
    shape.local_support_feature(d, &mut f);
    f
}

fn feature_vertices(f: &PolygonalFeature) -> BTreeSet<u32> {
    f.vids[..f.num_vertices].iter().map(|id| id.unpack().unwrap_vertex()).collect()
}

/// `d` turned by `angle` towards a random direction perpendicular to it.
fn tilted(d: Vector, angle: f64, rng: &mut Xoshiro256PlusPlus) -> Vector {
    let p = d.cross(random_unit(rng)).normalize();
    (d * angle.cos() as Real + p * angle.sin() as Real).normalize()
}

/// Is the 2-D projection of `t` strictly inside the convex polygon `poly` (counter-clockwise
/// seen from `n`)?
fn inside(poly: &[Vector], n: Vector, t: Vector) -> bool {
    (0..poly.len()).all(|i| (poly[(i + 1) % poly.len()] - poly[i]).cross(t - poly[i]).dot(n) > 0.0)
}

#[test]
fn support_points_equal_the_brute_force_argmax_on_a_pebble_hull() {
    let (poly, g, shape) = pebble();
    // 3000 points, all but a few of them hull corners.
    let n = shape.num_vertices();
    assert!((2000..=3000).contains(&n), "{n} hull corners");
    assert_eq!(shape.num_facets(), poly.facets.len());
    for (p, q) in poly.vertices.iter().zip(shape.points()) {
        assert_eq!(*q, to_vector(&(p - g)));
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let mut dirs: Vec<Vector> = (0..10_000).map(|_| random_unit(&mut rng)).collect();
    // Directions with ties and exact alignments too: axes and facet normals.
    dirs.extend([Vector::X, -Vector::X, Vector::Y, -Vector::Y, Vector::Z, -Vector::Z]);
    dirs.extend((0..shape.num_facets()).map(|f| shape.facet_normal(f)));
    // Unnormalised directions too.
    let n_dirs = dirs.len();
    let scaled: Vec<Vector> = dirs[..1000].iter().map(|&d| d * 3.5).collect();
    dirs.extend(scaled);
    for d in dirs {
        let best = shape.points().iter().map(|&p| dot64(p, d)).fold(f64::NEG_INFINITY, f64::max);
        let got = shape.local_support_point(d);
        assert_eq!(dot64(got, d), best, "direction {d:?}");
        assert_eq!(shape.support_point(&Pose::identity(), d), got);
    }
    assert!(n_dirs > 10_000);
}

#[test]
fn support_points_are_exact_with_ties_on_platonic_solids_and_boxes() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    let mut meshes: Vec<_> = Platonic::ALL.iter().map(|&p| generate::platonic(p)).collect();
    meshes.push(generate::cuboid(2.0, 1.0, 0.5));
    meshes.push(generate::noisy_cuboid(4.0, 2.0, 1.0, 6, 0.05, 4));
    for mesh in &meshes {
        let (_, shape) = shape_of(mesh);
        let mut dirs: Vec<Vector> = (0..2000).map(|_| random_unit(&mut rng)).collect();
        for x in [-1.0, 0.0, 1.0] {
            for y in [-1.0, 0.0, 1.0] {
                for z in [-1.0, 0.0, 1.0] {
                    if (x, y, z) != (0.0, 0.0, 0.0) {
                        dirs.push(Vector::new(x, y, z));
                    }
                }
            }
        }
        for d in dirs {
            let best = shape.points().iter().map(|&p| dot64(p, d)).fold(f64::NEG_INFINITY, f64::max);
            assert_eq!(dot64(shape.local_support_point(d), d), best);
        }
    }
}

/// The facet a contact feature comes from.
fn facet_of(feat: &PolygonalFeature) -> u32 {
    feat.fid.unpack().unwrap_face()
}

/// Whether `g` may stand for facet `f` as the contact towards `d` ("Resting on a stable facet" in
/// `HullShape`'s docs): `f` is unstable, `g` stable, and every kept corner of `g` is within the
/// touch tolerance of the support plane (with the f32 corners' rounding).
fn touched_stable_instead(shape: &HullShape, f: usize, g: u32, d: Vector) -> bool {
    let top = shape.points().iter().map(|&p| dot64(p, d)).fold(f64::NEG_INFINITY, f64::max);
    let floor = top - shape.touch_tolerance() * (1.0 + 1e-5) - 1e-6;
    !shape.rests_on(f)
        && shape.rests_on(g as usize)
        && shape.facet_support_corners(g as usize).iter().all(|&c| dot64(shape.points()[c as usize], d) >= floor)
}

/// For every facet: towards its normal the support feature is that facet, with its corners (all
/// of them up to four), or — for an unstable facet only — a stable facet the body touches
/// there; tilted by less than the feature angle and less than half the angle to any facet
/// sharing a corner, the same. Returns the tilted checks and the facets stood in for.
fn check_facet_features(poly: &Polyhedron, shape: &HullShape, rng: &mut Xoshiro256PlusPlus) -> (usize, usize) {
    let mut tilted_checks = 0;
    let mut stood_in = 0;
    for (f, facet) in poly.facets.iter().enumerate() {
        let n = to_vector(&facet.normal);
        let feat = feature(shape, n);
        assert_eq!(shape.support_feature_id(n), FeatureId::Face(f as u32));
        if facet_of(&feat) != f as u32 {
            assert!(
                touched_stable_instead(shape, f, facet_of(&feat), n),
                "facet {f}: contact from {}",
                facet_of(&feat)
            );
            stood_in += 1;
            continue;
        }
        let corners: BTreeSet<u32> = facet.vertices.iter().copied().collect();
        let got = feature_vertices(&feat);
        assert_eq!(feat.num_vertices, facet.vertices.len().min(4));
        assert!(got.is_subset(&corners), "facet {f}: {got:?} not in {corners:?}");
        if facet.vertices.len() <= 4 {
            assert_eq!(got, corners);
            // In loop order, with the facet's edges as sides.
            for k in 0..feat.num_vertices {
                assert_eq!(feat.vids[k], PackedFeatureId::vertex(facet.vertices[k]));
                assert_eq!(feat.eids[k], PackedFeatureId::edge(facet.edges[k]));
                assert_eq!(feat.vertices[k], shape.points()[facet.vertices[k] as usize]);
            }
        }
        // Smallest angle to a facet sharing a corner.
        let mut min_angle = f64::INFINITY;
        for &v in &facet.vertices {
            for &e in &poly.vertex_edges[v as usize] {
                for g in poly.edges[e as usize].facets {
                    if g as usize != f {
                        min_angle = min_angle.min(facet.normal.angle(&poly.facets[g as usize].normal));
                    }
                }
            }
        }
        let angle = (0.4 * min_angle).min(0.9 * DEFAULT_FEATURE_ANGLE);
        if angle > 1e-4 {
            for _ in 0..4 {
                let d = tilted(n, angle, rng);
                let got = facet_of(&feature(shape, d));
                assert!(
                    got == f as u32 || touched_stable_instead(shape, f, got, d),
                    "facet {f} tilted {angle}: contact from {got}"
                );
                tilted_checks += 1;
            }
        }
    }
    (tilted_checks, stood_in)
}

#[test]
fn support_features_are_the_hulls_own_facets() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    let (poly, _, shape) = pebble();
    let (tilted, stood_in) = check_facet_features(&poly, &shape, &mut rng);
    assert!(tilted > 4 * poly.facets.len() / 2, "{tilted} tilted checks");
    assert!(stood_in * 20 < poly.facets.len(), "{stood_in} of {} facets stood in for", poly.facets.len());
    for mesh in [generate::cuboid(2.0, 1.0, 0.5), generate::platonic(Platonic::Dodecahedron)] {
        let (poly, shape) = shape_of(&mesh);
        assert_eq!(check_facet_features(&poly, &shape, &mut rng), (4 * poly.facets.len(), 0));
    }
    let poly = prism(12, 0.3);
    let shape = HullShape::new(&poly, &Point3::origin(), 1.0);
    check_facet_features(&poly, &shape, &mut rng);
}

#[test]
fn the_micro_facets_parry_would_merge_stay_distinct() {
    let (poly, g, shape) = pebble();
    let pts: Vec<Vector> = poly.vertices.iter().map(|p| to_vector(&(p - g))).collect();
    let parry = ConvexPolyhedron::from_convex_hull(&pts).unwrap();
    // parry merges neighbours within ~1.5°: far fewer faces than our exact facets.
    assert!(parry.faces().len() * 2 < poly.facets.len(), "{} vs {}", parry.faces().len(), poly.facets.len());
    // Every stable facet is its own contact; an unstable one at most stands in a touched stable one.
    for f in 0..poly.facets.len() {
        let n = shape.facet_normal(f);
        let got = facet_of(&feature(&shape, n));
        if shape.rests_on(f) {
            assert_eq!(got, f as u32, "stable facet {f}");
        } else {
            assert!(got == f as u32 || touched_stable_instead(&shape, f, got, n), "facet {f}: contact from {got}");
        }
    }
    assert!((0..poly.facets.len()).any(|f| shape.rests_on(f)) && (0..poly.facets.len()).any(|f| !shape.rests_on(f)));
}

/// A box whose base is two facets 7·10⁻⁴ rad apart (one base corner lifted by 10⁻³), G over the
/// flat one: the base's stable facet A, its unstable neighbour B, and the angle between them.
fn ridged_box() -> (HullShape, u32, u32, f64) {
    let lift = 1e-3;
    let mut pts = vec![
        Point3::new(-1.0, -1.0, -0.5),
        Point3::new(1.0, -1.0, -0.5),
        Point3::new(-1.0, 1.0, -0.5),
        Point3::new(1.0, 1.0, -0.5 + lift),
    ];
    pts.extend(pts.clone().iter().map(|p| Point3::new(p.x, p.y, 0.5)));
    let poly = Polyhedron::new(&pts, DEFAULT_COPLANAR_TOL).unwrap();
    let g = Point3::new(-0.3, -0.3, 0.0);
    let shape = HullShape::new(&poly, &g, 1.0);
    let base = |x: f64, y: f64| {
        let c = (0..poly.facets.len()).filter(|&f| poly.facets[f].normal.z < -0.99);
        c.into_iter()
            .find(|&f| {
                poly.facets[f].vertices.iter().any(|&v| {
                    (poly.vertices[v as usize].x - x).abs() < 1e-9 && (poly.vertices[v as usize].y - y).abs() < 1e-9
                })
            })
            .unwrap() as u32
    };
    let (a, b) = (base(-1.0, -1.0), base(1.0, 1.0));
    assert_ne!(a, b);
    let angle = poly.facets[a as usize].normal.angle(&poly.facets[b as usize].normal);
    (shape, a, b, angle)
}

#[test]
fn a_body_tilted_towards_an_unstable_neighbour_keeps_the_contact_of_its_stable_facet() {
    let (shape, a, b, angle) = ridged_box();
    assert!(shape.rests_on(a as usize) && !shape.rests_on(b as usize));
    assert!((5e-4..1e-3).contains(&angle), "angle {angle}");
    let (na, nb) = (shape.facet_normal(a as usize), shape.facet_normal(b as usize));
    let towards = |t: f64| {
        let axis = na.cross(nb).normalize();
        (Rotation::from_axis_angle(axis, (t * angle) as Real) * na).normalize()
    };
    // Across the bisector, nearer B's normal: the closest facet is B, but the body still touches
    // A with all its corners (the lifted corner is 3·10⁻⁴ up, the far one 7·10⁻⁴), so A carries it.
    let d = towards(0.7);
    assert_eq!(shape.support_feature_id(d), FeatureId::Face(b));
    assert_eq!(facet_of(&feature(&shape, d)), a);
    assert_eq!(shape.support_facet(d), a);
    // Past B's plane the lifted corner is the lowest, A's far corner is 10⁻³ up: B carries it.
    assert_eq!(facet_of(&feature(&shape, towards(1.5))), b);
    // Towards A's normal, A.
    assert_eq!(facet_of(&feature(&shape, na)), a);
}

#[test]
fn feature_ids_classify_faces_edges_and_vertices_but_contact_features_are_facets() {
    let (poly, shape) = shape_of(&generate::cuboid(1.0, 1.0, 1.0));
    let face_with = |d: Vector| {
        // The polygonal feature is the facet at the support vertex closest to d.
        let f = feature(&shape, d);
        assert_eq!(f.num_vertices, 4);
        assert!(feature_vertices(&f).contains(&shape.support_vertex(d)));
        let FeatureId::Face(face) = f.fid.unpack() else { panic!("{:?}", f.fid.unpack()) };
        face
    };
    // Between two faces: an edge parallel to z.
    let d = Vector::new(1.0, 1.0, 0.0);
    let FeatureId::Edge(e) = shape.support_feature_id(d) else { panic!("{:?}", shape.support_feature_id(d)) };
    let [a, b] = poly.edges[e as usize].vertices;
    assert!([a, b].iter().all(|&v| shape.points()[v as usize].x == 0.5 && shape.points()[v as usize].y == 0.5));
    let _ = face_with(d);
    // Towards a corner: the vertex.
    let d = Vector::new(1.0, 1.0, 1.0);
    assert_eq!(shape.support_feature_id(d), FeatureId::Vertex(shape.support_vertex(d)));
    assert_eq!(shape.points()[shape.support_vertex(d) as usize], Vector::splat(0.5));
    let _ = face_with(d);
    // Just inside / just outside the feature angle from +x.
    let px = (0..6).find(|&f| shape.facet_normal(f).x > 0.99).unwrap() as u32;
    let inside_angle = 0.9 * DEFAULT_FEATURE_ANGLE;
    let d = Vector::new(inside_angle.cos() as Real, 0.0, inside_angle.sin() as Real);
    assert_eq!(shape.support_feature_id(d), FeatureId::Face(px));
    assert_eq!(face_with(d), px);
    let outside_angle = 1.2 * DEFAULT_FEATURE_ANGLE;
    let d = Vector::new(outside_angle.cos() as Real, 0.0, outside_angle.sin() as Real);
    assert!(matches!(shape.support_feature_id(d), FeatureId::Edge(_)), "edge x = z = 0.5");
    assert_eq!(face_with(d), px);
    // A wider feature angle reports the face.
    let wide = shape.clone().with_feature_angle(5f64.to_radians());
    assert_eq!(wide.support_feature_id(d), FeatureId::Face(px));
}

#[test]
fn facets_with_many_corners_keep_the_projection_of_g_and_the_lowest_corner() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let poly = prism(16, 0.2);
    let cap = poly.facets.iter().position(|f| f.normal.z < -0.99).unwrap();
    assert_eq!(poly.facets[cap].vertices.len(), 16);
    // G at the centre and off-centre (its projection near the cap's rim).
    for origin in [Point3::origin(), Point3::new(0.8, 0.1, 0.05), Point3::new(-0.3, -0.85, 0.0)] {
        let shape = HullShape::new(&poly, &origin, 1.0);
        let radius = shape.compute_local_bounding_sphere().radius;
        let mut reduced_around_lowest = 0;
        let n = shape.facet_normal(cap);
        let t = n * n.dot(shape.points()[poly.facets[cap].vertices[0] as usize]);
        let corners: Vec<Vector> =
            shape.facet_support_corners(cap).iter().map(|&c| shape.points()[c as usize]).collect();
        assert_eq!(corners.len(), 4);
        assert!(inside(&corners, n, t), "origin {origin}: static quadrilateral misses the projection of G");
        assert_eq!(feature_vertices(&feature(&shape, n)), shape.facet_support_corners(cap).into_iter().collect());
        // Tilted within the feature angle: the lowest corner is always in the feature, and the
        // feature still covers the projection of G.
        for _ in 0..200 {
            let d = tilted(n, 0.8 * DEFAULT_FEATURE_ANGLE, &mut rng);
            let f = feature(&shape, d);
            assert_eq!(f.fid, PackedFeatureId::face(cap as u32));
            // The lowest corner is in the feature, or within 1e-4 of the bounding radius of it.
            let lowest = shape.support_vertex(d);
            let deepest = f.vertices[..4].iter().map(|&p| dot64(p, d)).fold(f64::NEG_INFINITY, f64::max);
            let gap = dot64(shape.points()[lowest as usize], d) - deepest;
            assert!(gap <= 1e-4 * radius as f64 + 1e-12, "lowest corner {lowest} {gap} below the feature");
            reduced_around_lowest += feature_vertices(&f).contains(&lowest) as usize;
            assert!(inside(&f.vertices[..4], n, t));
            for k in 0..4 {
                let ids = [f.vids[k].unpack().unwrap_vertex(), f.vids[(k + 1) % 4].unpack().unwrap_vertex()];
                let is_edge = poly.edges.iter().position(|e| e.vertices == ids || e.vertices == [ids[1], ids[0]]);
                match is_edge {
                    Some(e) => assert_eq!(f.eids[k], PackedFeatureId::edge(e as u32)),
                    None => assert!(f.eids[k].unpack().unwrap_edge() as usize >= poly.edges.len()),
                }
            }
        }
        assert!(reduced_around_lowest > 190, "{reduced_around_lowest}");
    }
}

#[test]
fn bounds_are_tight_locally_and_conservative_in_any_pose() {
    let (_, _, shape) = pebble();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(9);
    let aabb = shape.compute_local_aabb();
    for k in 0..3 {
        let lo = shape.points().iter().map(|p| p[k]).fold(Real::INFINITY, Real::min);
        let hi = shape.points().iter().map(|p| p[k]).fold(Real::NEG_INFINITY, Real::max);
        assert_eq!((aabb.mins[k], aabb.maxs[k]), (lo, hi));
    }
    for _ in 0..200 {
        let axis = random_unit(&mut rng) * rng.random_range(0.0..3.0) as Real;
        let pose = Pose::from_parts(random_unit(&mut rng) * 5.0, Rotation::from_scaled_axis(axis));
        let world = shape.compute_aabb(&pose);
        let sphere = shape.compute_bounding_sphere(&pose);
        let tol = 1e-5;
        for &p in shape.points() {
            let q = pose * p;
            assert!((0..3).all(|k| q[k] >= world.mins[k] - tol && q[k] <= world.maxs[k] + tol));
            assert!((q - sphere.center).length() <= sphere.radius + tol);
        }
    }
}

#[test]
fn shape_trait_basics() {
    let (_, shape) = shape_of(&generate::cuboid(2.0, 1.0, 0.5));
    assert_eq!(shape.shape_type(), ShapeType::Custom);
    assert!(matches!(shape.as_typed_shape(), TypedShape::Custom(_)));
    assert!(shape.is_convex());
    assert!(shape.as_support_map().is_some());
    assert_eq!(shape.as_polygonal_feature_map().map(|p| p.1), Some(0.0));
    assert_eq!(shape.ccd_thickness(), 0.25);
    let boxed = shape.clone_dyn();
    assert_eq!(boxed.compute_local_aabb().maxs, Vector::new(1.0, 0.5, 0.25));
    // Mass properties at density 3: m = 3, I = m (b² + c²)/12 … about G = origin.
    let mp = shape.mass_properties(3.0);
    assert!((mp.mass() - 3.0).abs() < 1e-5);
    assert!(mp.local_com.length() < 1e-6);
    let mut inertia = mp.principal_inertia().to_array();
    inertia.sort_by(f32::total_cmp);
    let want = [3.0 * (1.0 + 0.25) / 12.0, 3.0 * (4.0 + 0.25) / 12.0, 3.0 * (4.0 + 1.0) / 12.0];
    assert!(inertia.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-5), "{inertia:?}");
    // Scaling is exact and keeps the facets.
    let scaled = shape.scale_dyn(Vector::new(2.0, 1.0, 3.0), 0).unwrap();
    assert_eq!(scaled.compute_local_aabb().maxs, Vector::new(2.0, 0.5, 0.75));
    assert!(shape.scale_dyn(Vector::new(-1.0, 1.0, 1.0), 0).is_none());
    let scaled = shape.scaled(Vector::new(2.0, 1.0, 3.0)).unwrap();
    assert_eq!(scaled.num_facets(), 6);
    assert_eq!(feature(&scaled, Vector::Z).num_vertices, 4);
    // Feature normals.
    let f = shape.support_feature_id(Vector::X);
    assert_eq!(shape.feature_normal_at_point(0, f, Vector::ZERO), Some(Vector::X));
}

#[test]
fn ray_casts_and_point_projections_match_parry_on_a_box() {
    let (_, shape) = shape_of(&generate::cuboid(2.0, 1.0, 0.5));
    let cuboid = Cuboid::new(Vector::new(1.0, 0.5, 0.25));
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(13);
    let mut hits = 0;
    for _ in 0..500 {
        let origin = random_unit(&mut rng) * 3.0;
        let ray = Ray::new(origin, (random_unit(&mut rng) * 0.3 - origin.normalize()).normalize());
        let a = shape.cast_local_ray(&ray, 10.0, true);
        let b = cuboid.cast_local_ray(&ray, 10.0, true);
        assert_eq!(a.is_some(), b.is_some(), "{ray:?}");
        if let (Some(a), Some(b)) = (a, b) {
            assert!((a - b).abs() < 1e-4, "{a} vs {b}");
            hits += 1;
        }
        let p = random_unit(&mut rng) * rng.random_range(0.0..2.0) as Real;
        let (pa, pb) = (shape.project_local_point(p, false), cuboid.project_local_point(p, false));
        assert_eq!(pa.is_inside, pb.is_inside);
        assert!((pa.point - pb.point).length() < 1e-4, "{p:?}: {:?} vs {:?}", pa.point, pb.point);
    }
    assert!(hits > 100);
    let (proj, feat) = shape.project_local_point_and_get_feature(Vector::new(3.0, 0.1, 0.0));
    assert!((proj.point - Vector::new(1.0, 0.1, 0.0)).length() < 1e-5);
    assert!(matches!(feat, FeatureId::Face(_)));
}

/// Contacts straight from parry's default dispatcher (the path rapier's narrow phase takes).
fn dispatcher_contacts(ground: &dyn Shape, ground_pose: Pose, body: &HullShape, body_pose: Pose) -> Vec<f32> {
    let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
    let pos12 = ground_pose.inverse() * body_pose;
    DefaultQueryDispatcher.contact_manifolds(&pos12, ground, body, 0.01, &mut manifolds, &mut None).unwrap();
    manifolds.iter().flat_map(|m| m.points.iter().map(|p| p.dist)).collect()
}

#[test]
fn the_default_dispatcher_makes_contacts_with_a_half_space_and_a_cuboid() {
    let (_, cube) = shape_of(&generate::cuboid(1.0, 1.0, 1.0));
    let half_space = HalfSpace::new(Vector::Y);
    let slab = Cuboid::new(Vector::new(5.0, 1.0, 5.0));
    let slab_pose = Pose::from_translation(Vector::new(0.0, -1.0, 0.0));
    let resting = Pose::from_translation(Vector::new(0.1, 0.499, -0.2));
    for (ground, pose) in [(&half_space as &dyn Shape, Pose::identity()), (&slab as &dyn Shape, slab_pose)] {
        // Resting on a face: its four corners, 1e-3 deep.
        let d = dispatcher_contacts(ground, pose, &cube, resting);
        assert!(d.len() >= 4 && d.iter().filter(|&&x| (x + 1e-3).abs() < 1e-4).count() >= 4, "{d:?}");
        // Both orders.
        let mut m: Vec<ContactManifold<(), ()>> = Vec::new();
        DefaultQueryDispatcher
            .contact_manifolds(&(resting.inverse() * pose), &cube, ground, 0.01, &mut m, &mut None)
            .unwrap();
        assert!(m[0].points.len() >= 4);
        // Balanced on an edge and on a corner.
        let edge = Pose::from_parts(
            Vector::new(0.0, 0.5f32.sqrt() - 1e-3, 0.0),
            Rotation::from_axis_angle(Vector::Z, std::f32::consts::FRAC_PI_4),
        );
        let d = dispatcher_contacts(ground, pose, &cube, edge);
        assert!(d.iter().filter(|&&x| x < 0.0).count() >= 2, "{d:?}");
        // Far above: nothing.
        assert!(dispatcher_contacts(ground, pose, &cube, Pose::from_translation(Vector::Y * 3.0)).is_empty());
    }
}

/// A minimal rapier world with one ground collider (y = 0 is the ground's top).
struct World {
    bodies: RigidBodySet,
    colliders: ColliderSet,
    pipeline: PhysicsPipeline,
    params: IntegrationParameters,
    broad: DefaultBroadPhase,
    narrow: NarrowPhase,
    islands: IslandManager,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    ccd: CCDSolver,
}

#[derive(Clone, Copy, Debug)]
enum Ground {
    HalfSpace,
    Cuboid,
}

impl World {
    fn new(ground: Ground) -> World {
        let mut w = World {
            bodies: RigidBodySet::new(),
            colliders: ColliderSet::new(),
            pipeline: PhysicsPipeline::new(),
            params: IntegrationParameters::default(),
            broad: DefaultBroadPhase::new(),
            narrow: NarrowPhase::new(),
            islands: IslandManager::new(),
            impulse_joints: ImpulseJointSet::new(),
            multibody_joints: MultibodyJointSet::new(),
            soft_bodies: SoftBodySet::new(),
            ccd: CCDSolver::new(),
        };
        let collider = match ground {
            Ground::HalfSpace => ColliderBuilder::new(SharedShape::halfspace(Vector::Y)),
            Ground::Cuboid => ColliderBuilder::cuboid(20.0, 1.0, 20.0).translation(Vector::new(0.0, -1.0, 0.0)),
        };
        w.colliders.insert(collider.friction(0.6).build());
        w
    }

    fn add(&mut self, shape: SharedShape, pose: Pose) -> RigidBodyHandle {
        let h = self.bodies.insert(RigidBodyBuilder::dynamic().pose(pose).build());
        let c = ColliderBuilder::new(shape).density(1.0).friction(0.6).restitution(0.0).build();
        self.colliders.insert_with_parent(c, h, &mut self.bodies);
        h
    }

    /// A body with explicit mass properties (collider density 0), as the drop simulator does.
    fn add_with_mass(
        &mut self,
        shape: SharedShape,
        pose: Pose,
        mass: rapier3d::prelude::MassProperties,
    ) -> RigidBodyHandle {
        let h = self.bodies.insert(RigidBodyBuilder::dynamic().can_sleep(false).pose(pose).build());
        let c = ColliderBuilder::new(shape).density(0.0).mass_properties(mass).friction(0.6).build();
        self.colliders.insert_with_parent(c, h, &mut self.bodies);
        h
    }

    fn run(&mut self, seconds: f32) {
        for _ in 0..(seconds / self.params.dt).round() as usize {
            self.pipeline.step(
                Vector::new(0.0, -9.81, 0.0),
                &self.params,
                &mut self.islands,
                &mut self.broad,
                &mut self.narrow,
                &mut self.bodies,
                &mut self.colliders,
                &mut self.impulse_joints,
                &mut self.multibody_joints,
                &mut self.soft_bodies,
                &mut self.ccd,
                &(),
                &(),
            );
        }
    }

    fn pose(&self, h: RigidBodyHandle) -> Pose {
        *self.bodies[h].position()
    }
}

/// The body-frame axis (0..6: +x, −x, +y, −y, +z, −z) pointing most nearly down, and its angle
/// to down (degrees).
fn down_axis(pose: &Pose) -> (usize, f32) {
    let down = pose.rotation.inverse() * -Vector::Y;
    let axes = [Vector::X, -Vector::X, Vector::Y, -Vector::Y, Vector::Z, -Vector::Z];
    let (i, a) = axes.iter().enumerate().map(|(i, a)| (i, a.dot(down))).max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    (i, a.clamp(-1.0, 1.0).acos().to_degrees())
}

#[test]
fn a_cube_released_above_the_ground_comes_to_rest_on_a_face() {
    let (_, cube) = shape_of(&generate::cuboid(1.0, 1.0, 1.0));
    let shared = SharedShape::new(cube);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(21);
    for ground in [Ground::HalfSpace, Ground::Cuboid] {
        for k in 0..6 {
            let mut w = World::new(ground);
            let rot = Rotation::from_scaled_axis(random_unit(&mut rng) * rng.random_range(0.0..3.1) as Real);
            let h = w.add(shared.clone(), Pose::from_parts(Vector::new(0.0, 0.9 + 0.05 * k as Real, 0.0), rot));
            w.run(4.0);
            let pose = w.pose(h);
            let (_, angle) = down_axis(&pose);
            assert!(angle < 1.0, "{ground:?} drop {k}: lowest facet normal {angle}° from down");
            assert!((pose.translation.y - 0.5).abs() < 1e-2, "{ground:?} drop {k}: height {}", pose.translation.y);
            assert!(w.bodies[h].linvel().length() < 1e-2);
        }
    }
}

#[test]
fn a_box_placed_on_its_largest_face_stays_there() {
    let (_, shape) = shape_of(&generate::cuboid(2.0, 1.0, 0.5));
    for ground in [Ground::HalfSpace, Ground::Cuboid] {
        let mut w = World::new(ground);
        // Largest face (2 × 1, normal −z in the body frame) down.
        let rot = Rotation::from_axis_angle(Vector::X, -std::f32::consts::FRAC_PI_2);
        let h = w.add(SharedShape::new(shape.clone()), Pose::from_parts(Vector::new(0.3, 0.25, -0.1), rot));
        w.run(3.0);
        let pose = w.pose(h);
        assert_eq!(down_axis(&pose).0, 5, "{ground:?}");
        assert!(down_axis(&pose).1 < 0.1, "{ground:?}: tilted {}°", down_axis(&pose).1);
        assert!((pose.translation.y - 0.25).abs() < 1e-2, "{ground:?}: height {}", pose.translation.y);
        let drift = (pose.translation - Vector::new(0.3, pose.translation.y, -0.1)).length();
        assert!(drift < 1e-3, "{ground:?}: slid {drift}");
    }
}

#[test]
fn drops_of_a_box_end_on_the_same_face_as_with_a_cuboid_collider() {
    let (_, shape) = shape_of(&generate::cuboid(2.0, 1.0, 0.5));
    let hull = SharedShape::new(shape);
    let cuboid = SharedShape::cuboid(1.0, 0.5, 0.25);
    let deg = |a: f32| a.to_radians();
    // (initial orientation, release height of G, expected resting axis)
    let rx = |a: f32| Rotation::from_axis_angle(Vector::X, deg(a));
    let end_down = Rotation::from_axis_angle(Vector::Z, deg(90.0)); // body −x down
                                                                    // (initial orientation, release height of G, expected body axis down: 1 = −x, 3 = −y,
                                                                    // 4 = +z, 5 = −z). Gravity is −y.
    let cases = [
        // On the largest face (−z down), tilted 10° about the long axis (critical 63°): rocks back.
        (rx(-80.0), 0.35, 5),
        // Standing on an end, tilted 5° towards its thin side (critical 14°): stays.
        (rx(5.0) * end_down, 1.03, 1),
        // Standing on an end, tilted 30° towards its thin side: topples onto a large face.
        (rx(30.0) * end_down, 1.0, 4),
        // On a side (−y down), tilted 45° (critical 26.6°): topples onto a large face.
        (rx(45.0), 0.55, 4),
        // On a side, tilted 15°: rocks back.
        (rx(-15.0), 0.56, 3),
    ];
    for ground in [Ground::HalfSpace, Ground::Cuboid] {
        for (i, &(rot, height, want)) in cases.iter().enumerate() {
            let mut got = Vec::new();
            for shape in [&hull, &cuboid] {
                let mut w = World::new(ground);
                let h = w.add(shape.clone(), Pose::from_parts(Vector::new(0.0, height, 0.0), rot));
                w.run(4.0);
                got.push(down_axis(&w.pose(h)));
            }
            assert_eq!(got[0].0, got[1].0, "{ground:?} case {i}: HullShape {:?} vs cuboid {:?}", got[0], got[1]);
            assert_eq!(got[0].0, want, "{ground:?} case {i}: {got:?}");
            assert!(got[0].1 < 1.0 && got[1].1 < 1.0, "{ground:?} case {i}: {got:?}");
        }
    }
}

/// Regression: with edge/vertex contact features (instead of facets), a needle toppling onto its
/// side got contacts on its leading edge only, overshot into the ground and locked into an
/// undamped rocking cycle 1.2 cm deep. It must come to rest like a cuboid collider.
#[test]
fn a_toppling_needle_lands_on_its_side_like_a_cuboid() {
    let (_, needle) = shape_of(&generate::cuboid(0.05, 1.0, 0.05));
    let m = 0.05 * 0.05;
    let inertia = Vector::new(m * 1.0025 / 12.0, m * 0.005 / 12.0, m * 1.0025 / 12.0);
    for offset in [0.9, 0.95] {
        // G off-centre towards +x: the needle stands on a base it cannot hold and topples.
        let com = Vector::new(0.025 * offset, 0.0, 0.0);
        let mut got = Vec::new();
        for shape in [SharedShape::new(needle.clone()), SharedShape::cuboid(0.025, 0.5, 0.025)] {
            let mut w = World::new(Ground::HalfSpace);
            let mass = rapier3d::prelude::MassProperties::new(com, m, inertia);
            let h = w.add_with_mass(shape, Pose::from_translation(Vector::new(0.0, 0.5, 0.0)), mass);
            w.run(10.0);
            let pose = w.pose(h);
            got.push((down_axis(&pose), pose.translation.y, w.bodies[h].angvel().length()));
        }
        for (i, &((axis, angle), y, spin)) in got.iter().enumerate() {
            assert!(!(2..=3).contains(&axis), "{offset} {i}: standing ({got:?})");
            assert!(angle < 0.5 && (y - 0.025).abs() < 1e-3 && spin < 1e-2, "{offset} {i}: {got:?}");
        }
        assert_eq!(got[0].0 .0, got[1].0 .0, "{got:?}");
    }
}

#[test]
fn solid_mass_properties_replace_the_hulls() {
    let mesh = generate::pebble([1.0, 0.7, 0.5], 0.3, 400, 2);
    let poly = Polyhedron::new(&mesh.vertices, DEFAULT_COPLANAR_TOL).unwrap();
    let solid = MassProperties::of(&mesh).unwrap();
    let g = solid.center_of_mass;
    for scale in [1.0, 0.01] {
        let hull_mass = HullShape::new(&poly, &g, scale).mass_properties(2.0);
        let shape = HullShape::new(&poly, &g, scale).with_solid_mass(&solid);
        let mp = shape.mass_properties(2.0);
        // The rough pebble's hull is visibly larger than the solid.
        assert!(hull_mass.mass() > mp.mass() * 1.01);
        assert!(hull_mass.local_com.length() > 1e-4 * scale as f32);
        let s3 = scale.powi(3);
        assert!(((mp.mass() as f64) - 2.0 * solid.volume * s3).abs() < 1e-5 * 2.0 * solid.volume * s3);
        assert!(mp.local_com.length() < 1e-6 * scale as f32);
        let mut want: Vec<f64> = solid.principal_moments.iter().map(|i| 2.0 * i * scale.powi(5)).collect();
        let mut got: Vec<f64> = mp.principal_inertia().to_array().iter().map(|&i| i as f64).collect();
        want.sort_by(f64::total_cmp);
        got.sort_by(f64::total_cmp);
        assert!(got.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-4 * b), "{got:?} vs {want:?}");
    }
}

#[test]
fn a_pebble_rests_on_its_own_stable_micro_facets() {
    let (poly, g, shape) = pebble();
    // Stable facets (G projects inside), by the distance from that projection to the border.
    let mut stable: Vec<(f64, usize)> = poly
        .facets
        .iter()
        .enumerate()
        .filter_map(|(f, facet)| {
            let n = facet.normal;
            let p = g - n * (n.dot(&g.coords) - facet.offset);
            let k = facet.vertices.len();
            let margin = (0..k)
                .map(|i| {
                    let (a, b) = (
                        poly.vertices[facet.vertices[i] as usize],
                        poly.vertices[facet.vertices[(i + 1) % k] as usize],
                    );
                    (b - a).cross(&(p - a)).dot(&n) / (b - a).norm()
                })
                .fold(f64::INFINITY, f64::min);
            (margin > 0.0).then_some((margin, f))
        })
        .collect();
    stable.sort_by(|a, b| b.0.total_cmp(&a.0));
    assert!(stable.len() >= 3);
    let mesh = generate::pebble([1.0, 0.7, 0.5], 0.02, 3000, 1);
    let shared = SharedShape::new(shape.clone().with_solid_mass(&MassProperties::of(&mesh).unwrap()));
    for &(margin, f) in &stable[..8] {
        let n = to_vector(&poly.facets[f].normal);
        // Facet f down, its plane on the ground.
        let rot = Rotation::from_rotation_arc(n, -Vector::Y);
        let height = (poly.facets[f].offset - poly.facets[f].normal.dot(&g.coords)) as Real;
        let mut w = World::new(Ground::HalfSpace);
        let h = w.add(shared.clone(), Pose::from_parts(Vector::new(0.0, height + 1e-4, 0.0), rot));
        w.run(3.0);
        let pose = w.pose(h);
        let down = pose.rotation.inverse() * -Vector::Y;
        let closest = (0..shape.num_facets())
            .max_by(|&a, &b| shape.facet_normal(a).dot(down).total_cmp(&shape.facet_normal(b).dot(down)))
            .unwrap();
        assert_eq!(closest, f, "facet {f} (margin {margin:.2e}) left for {closest}");
        assert_eq!(shape.support_facet(down), f as u32);
    }
}
