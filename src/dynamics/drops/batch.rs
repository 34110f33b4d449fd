//! Many independent drops in one rapier world (batched drops): the per-step cost of rapier's
//! pipeline (broad phase, island bookkeeping, solver set-up and its worker stages) is paid once per
//! step for the whole batch instead of once per drop.
//!
//! The stones of a batch meet only the ground (collision groups [`crate::dynamics::engine::world::stone_groups`]),
//! so each stone is its own island and its contact constraints involve only itself and the
//! kinematic ground. Rapier's solver packs the contact constraints of different bodies into the
//! lanes of its SIMD vectors, but every lane is computed by the same lane-wise operations, a
//! constraint touches only its own body's velocities, and a body's constraints keep their
//! order; so a stone's floating-point history is the same whatever shares the world with it.
//! This is measured, not assumed: `tests/batch.rs` checks that every drop's outcome (facet,
//! flock, simulated time and final height, as f64 bit patterns) is identical to the same drop
//! alone in its world ([`crate::dynamics::drops::simulate::simulate`]), for batch sizes 1, 7 and 32 and for 1 and
//! 2 threads.
//!
//! A finished stone (at rest, decided by the certificate, or at the time cap, by the same
//! [`Progress`] rule as a single run) is removed at once and the next drop of the queue is
//! inserted, so the batch stays full until the queue runs dry.
//!
//! With [`crate::dynamics::engine::params::Flight::Free`] a stone clear of the ground leaves the world and flies
//! outside rapier ([`crate::dynamics::engine::flight`]) until the exact instant its clearance falls to
//! [`flight::CONTACT_CLEARANCE`], where it re-enters the world (part-way through a step: its
//! clock then runs late by the rest of that step, which the reported time takes off); the world
//! is stepped only while some stone is in it. Its step count, certificate checks and rest rule are those of a stone in
//! the world (the same [`Progress`]), and its flight depends on nothing but its own state, so the
//! outcomes are again the same for any batch size and thread count (`tests/flight.rs`).

use crate::dynamics::drops::launch::{outcome, release_height, DropOutcome, Release};
use crate::dynamics::drops::params::DropParams;
use crate::dynamics::engine::body::Body;
use crate::dynamics::engine::contact::{step_world, ContactLaw};
use crate::dynamics::engine::flight::{self, FreeBody};
use crate::dynamics::engine::impact;
use crate::dynamics::engine::impact::ImpactWorld;
use crate::dynamics::engine::rest::{RestKind, RestSample};
use crate::dynamics::engine::run::{Certificate, Progress};
use crate::dynamics::engine::world::{body_state, ground_world, insert_stone, normal_impulse, BodyState};
use crate::dynamics::stone::Stone;
use crate::{Vec3, GRAVITY};
use nalgebra::UnitQuaternion;
use rapier3d::prelude::{ColliderHandle, PhysicsWorld, RigidBodyHandle};

/// Where a stone of the batch is.
enum Place {
    /// A body of the rapier world.
    World { handle: RigidBodyHandle, collider: ColliderHandle },
    /// Clear of the ground, in free flight outside rapier ([`crate::dynamics::engine::flight`]).
    Air(FreeBody),
    /// In an impact that one step could not resolve: in a world of its own, sub-stepped
    /// ([`crate::dynamics::engine::impact`]).
    Impact(Box<ImpactWorld>),
}

/// One stone in flight in a batch.
struct Slot {
    index: u64,
    place: Place,
    progress: Progress,
    /// How far (s) the stone's clock runs behind the step count: the unused parts of the steps
    /// in which it landed ([`flight::FreeBody::fly`]).
    lag: f64,
    /// The deepest penetration of the ground after any of its steps or sub-steps so far (R_max,
    /// [`crate::dynamics::engine::world::penetration`]).
    deepest: f64,
}

/// Simulate the drops of `queue` (drop index and release, in the order given) with at most
/// `capacity` stones in one world at a time, calling `on_done` with each outcome as its drop
/// finishes (in the order they finish), and showing `observe` every stone's state after every
/// step (its drop index and state, e.g. to measure the contact's compression; `&mut |_, _| {}`
/// to observe nothing). Every outcome equals that of [`crate::dynamics::drops::simulate::simulate`]
/// for the same drop (module docs). With [`crate::dynamics::engine::params::Flight::Free`] a stone clear of the
/// ground leaves the world and flies outside rapier ([`crate::dynamics::engine::flight`]) until it is about to
/// land.
pub fn simulate_batch(
    stone: &Stone,
    p: &DropParams,
    cert: &dyn Certificate,
    capacity: usize,
    queue: &mut dyn Iterator<Item = (u64, Release)>,
    on_done: &mut dyn FnMut(DropOutcome),
    observe: &mut dyn FnMut(u64, &BodyState),
) {
    let capacity = capacity.max(1);
    let free_flight = flight::applies(&p.sim);
    let damping = flight::Damping::of(&p.sim);
    let inertia = flight::Inertia::new(stone.body.inertia);
    let (mut world, _ground, ground_collider) = ground_world(&p.sim);
    let law = ContactLaw::of(&p.sim.contact);
    let mut slots: Vec<Slot> = Vec::with_capacity(capacity);
    // The stones in the world this step (a buffer kept across steps: no allocation per step).
    let mut in_world: Vec<(RigidBodyHandle, ColliderHandle)> = Vec::with_capacity(capacity);
    // Impact worlds no longer in use, kept for the next impact (a rapier world is costly to
    // build; one that held another stone behaves the same: `tests/batch.rs`, `tests/flight.rs`).
    let mut spare: Vec<Box<ImpactWorld>> = Vec::new();
    let mut queue = queue.fuse();
    loop {
        while slots.len() < capacity {
            let Some((index, release)) = queue.next() else { break };
            let z0 = release_height(stone, p, &release);
            let free = FreeBody::new(z0, release.linvel, release.orientation, &release.angvel);
            let place = if free_flight {
                land_if_due(&mut world, &mut spare, &stone.body, p, free)
            } else {
                enter_world(&mut world, &mut spare, &stone.body, p, &free)
            };
            slots.push(Slot {
                index,
                place,
                progress: Progress::new(&p.sim, 0, RestKind::Speeds),
                lag: 0.0,
                deepest: 0.0,
            });
        }
        if slots.is_empty() {
            return;
        }
        in_world.clear();
        in_world.extend(slots.iter().filter_map(|s| match s.place {
            Place::World { handle, collider } => Some((handle, collider)),
            Place::Air(_) | Place::Impact(_) => None,
        }));
        if !in_world.is_empty() {
            step_world(&mut world, &law, &stone.body, ground_collider, &in_world);
        }
        let mut k = 0;
        while k < slots.len() {
            let s = &mut slots[k];
            let mut landed = false;
            let state = match &mut s.place {
                Place::World { handle, .. } => {
                    // The ground of a drop is the fixed plane z = 0.
                    let state = body_state(&world.bodies[*handle], &stone.body);
                    s.deepest = s.deepest.max(stone.body.support_climb(&state.down) - state.z);
                    state
                }
                Place::Air(b) => {
                    if let flight::Flew::Landed(t) =
                        b.fly(p.sim.numerics.dt, &inertia, damping, &|d| stone.body.support_climb(d))
                    {
                        s.lag += p.sim.numerics.dt - t;
                        landed = true;
                    }
                    air_state(b, &stone.body)
                }
                Place::Impact(w) => {
                    let n = {
                        let (s, q) = w.state(&stone.body);
                        impact::substeps(&stone.body, &q, s.z, &s.linvel, &s.angvel, p.sim.numerics.dt)
                    };
                    s.deepest = s.deepest.max(w.step(n, &law, &stone.body));
                    w.state(&stone.body).0
                }
            };
            observe(s.index, &state);
            // The ground never moves here and the speed rule reads no position.
            let sample = RestSample { state: &state, ground_velocity: Vec3::zeros(), offset: Vec3::zeros() };
            match s.progress.after_step(&sample, cert) {
                None => {
                    if free_flight {
                        let place = std::mem::replace(
                            &mut s.place,
                            Place::Air(FreeBody::new(0.0, Vec3::zeros(), Default::default(), &Vec3::zeros())),
                        );
                        s.place =
                            next_place(&mut world, &mut spare, &stone.body, p, ground_collider, place, &state, landed);
                    }
                    k += 1;
                }
                Some(end) => {
                    let s = slots.swap_remove(k);
                    match s.place {
                        Place::World { handle, .. } => {
                            world.remove_body(handle);
                        }
                        Place::Impact(w) => spare.push(w),
                        Place::Air(_) => {}
                    }
                    let mut o = outcome(stone, p, &end, s.index);
                    o.time -= s.lag;
                    o.deepest_penetration = s.deepest;
                    on_done(o);
                }
            }
        }
    }
}

/// Insert the stone in the state `b` into the world (or, if one step could not resolve its
/// impact, into a world of its own: [`crate::dynamics::engine::impact`]).
fn enter_world(
    world: &mut PhysicsWorld,
    spare: &mut Vec<Box<ImpactWorld>>,
    body: &Body,
    p: &DropParams,
    b: &FreeBody,
) -> Place {
    let state = air_state(b, body);
    if flight::applies(&p.sim)
        && impact::substeps(body, &b.orientation, b.z, &b.linvel, &state.angvel, p.sim.numerics.dt) > 1
    {
        return Place::Impact(impact_world(spare, body, p, &b.orientation, &state));
    }
    let (handle, collider) = insert_stone(world, body, &p.sim, &b.orientation, b.z, &b.linvel, &b.angvel());
    Place::World { handle, collider }
}

/// Keep a released stone `b` in the air while it is clear of the ground ([`flight::airborne`]);
/// else insert it.
fn land_if_due(
    world: &mut PhysicsWorld,
    spare: &mut Vec<Box<ImpactWorld>>,
    body: &Body,
    p: &DropParams,
    b: FreeBody,
) -> Place {
    if flight::airborne(flight::clearance(b.z, body.support_climb(&b.down()))) {
        Place::Air(b)
    } else {
        enter_world(world, spare, body, p, &b)
    }
}

/// An impact world holding the stone in `state` with orientation `q`: a spare one if there is,
/// else a new one.
fn impact_world(
    spare: &mut Vec<Box<ImpactWorld>>,
    body: &Body,
    p: &DropParams,
    q: &UnitQuaternion<f64>,
    state: &BodyState,
) -> Box<ImpactWorld> {
    match spare.pop() {
        Some(mut w) => {
            w.reset(body, &p.sim, q, state);
            w
        }
        None => Box::new(ImpactWorld::new(body, &p.sim, q, state)),
    }
}

/// Where a stone goes after a step that ended in `state` (free flight, [`flight::applies`]): a
/// stone that `landed` enters the world; one that the ground did not push and that ended clear
/// of it ([`flight::may_take_off`]) leaves for free flight; one whose next step could bring a
/// hull corner down by more than its clearance plus
/// [`impact::IMPACT_APPROACH`] ([`impact::substeps`]) goes to (or stays in) a world of its own,
/// and comes back to the shared world once one step will do.
#[allow(clippy::too_many_arguments)]
fn next_place(
    world: &mut PhysicsWorld,
    spare: &mut Vec<Box<ImpactWorld>>,
    body: &Body,
    p: &DropParams,
    ground: ColliderHandle,
    place: Place,
    state: &BodyState,
    landed: bool,
) -> Place {
    let clear = || flight::may_take_off(flight::clearance(state.z, body.support_climb(&state.down)));
    let free = |q| FreeBody::new(state.z, state.linvel, q, &state.angvel);
    match place {
        Place::Air(b) if landed => enter_world(world, spare, body, p, &b),
        Place::Air(b) => Place::Air(b),
        Place::World { handle, collider } => {
            let pushed = normal_impulse(world, ground, collider) > 0.0;
            let take_off = !pushed && clear();
            let q = crate::dynamics::engine::convert::quat_back(world.bodies[handle].rotation());
            if !take_off && impact::substeps(body, &q, state.z, &state.linvel, &state.angvel, p.sim.numerics.dt) == 1 {
                return Place::World { handle, collider };
            }
            world.remove_body(handle);
            if take_off {
                Place::Air(free(q))
            } else {
                Place::Impact(impact_world(spare, body, p, &q, state))
            }
        }
        Place::Impact(w) => {
            let q = w.state(body).1;
            if w.normal_impulse() == 0.0 && clear() {
                spare.push(w);
                Place::Air(free(q))
            } else if impact::substeps(body, &q, state.z, &state.linvel, &state.angvel, p.sim.numerics.dt) == 1 {
                spare.push(w);
                enter_world(world, spare, body, p, &free(q))
            } else {
                Place::Impact(w)
            }
        }
    }
}

/// The state of a stone in free flight (as [`body_state`] reads it off a rapier body).
fn air_state(b: &FreeBody, body: &Body) -> BodyState {
    let down = b.orientation.inverse() * -Vec3::z();
    let level = b.z + b.kinetic_energy(&body.inertia) / GRAVITY;
    BodyState { down, z: b.z, linvel: b.linvel, angvel: b.angvel(), level }
}
