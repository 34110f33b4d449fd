//! Many independent drops in one rapier world (issue 16): the per-step cost of rapier's pipeline
//! (broad phase, island bookkeeping, solver set-up and its worker stages) is paid once per step
//! for the whole batch instead of once per drop.
//!
//! The stones of a batch meet only the ground (collision groups [`super::world::stone_groups`]),
//! so each stone is its own island and its contact constraints involve only itself and the
//! kinematic ground. Rapier's solver packs the contact constraints of different bodies into the
//! lanes of its SIMD vectors, but every lane is computed by the same lane-wise operations, a
//! constraint touches only its own body's velocities, and a body's constraints keep their
//! order; so a stone's floating-point history is the same whatever shares the world with it.
//! This is measured, not assumed: `tests/batch.rs` checks that every drop's outcome (facet,
//! flock, simulated time and final height, as f64 bit patterns) is identical to the same drop
//! alone in its world ([`super::drop::simulate`]), for batch sizes 1, 7 and 32 and for 1 and
//! 2 threads.
//!
//! A finished stone (at rest, decided by the certificate, or at the time cap, by the same
//! [`Progress`] rule as a single run) is removed at once and the next drop of the queue is
//! inserted, so the batch stays full until the queue runs dry.
//!
//! With [`super::params::Flight::Free`] a stone clear of the ground leaves the world and flies
//! outside rapier ([`super::flight`]) until it is about to land; the world is stepped only while
//! some stone is in it. Its step count, certificate checks and rest rule are those of a stone in
//! the world (the same [`Progress`]), and its flight depends on nothing but its own state, so the
//! outcomes are again the same for any batch size and thread count (`tests/flight.rs`).

use super::flight::{self, FreeBody};
use super::launch::{outcome, release_height, DropOutcome, Release};
use super::params::DropParams;
use super::run::{Certificate, Progress, RestKind, RestSample};
use super::stone::{Body, Stone};
use super::world::{body_state, ground_world, insert_stone, normal_impulse, step_world, BodyState, ContactLaw};
use crate::Vec3;
use crate::GRAVITY;
use nalgebra::Matrix3;
use rapier3d::prelude::{ColliderHandle, PhysicsWorld, RigidBodyHandle};

/// Where a stone of the batch is.
#[derive(Clone, Copy)]
enum Place {
    /// A body of the rapier world.
    World { handle: RigidBodyHandle, collider: ColliderHandle },
    /// Clear of the ground, in free flight outside rapier ([`super::flight`]).
    Air(FreeBody),
}

/// One stone in flight in a batch.
struct Slot {
    index: u64,
    place: Place,
    progress: Progress,
}

/// Simulate the drops of `queue` (drop index and release, in the order given) with at most
/// `capacity` stones in one world at a time, calling `on_done` with each outcome as its drop
/// finishes (in the order they finish). Every outcome equals that of [`super::drop::simulate`]
/// for the same drop (module docs). With [`super::params::Flight::Free`] a stone clear of the
/// ground leaves the world and flies outside rapier ([`super::flight`]) until it is about to
/// land.
pub fn simulate_batch(
    stone: &Stone,
    p: &DropParams,
    cert: &dyn Certificate,
    capacity: usize,
    queue: &mut dyn Iterator<Item = (u64, Release)>,
    on_done: &mut dyn FnMut(DropOutcome),
) {
    let capacity = capacity.max(1);
    let free_flight = flight::applies(p);
    let inertia = stone.body.inertia;
    let inertia_inv = inertia.try_inverse().unwrap_or_else(Matrix3::identity);
    let (mut world, _ground, ground_collider) = ground_world(p);
    let law = ContactLaw::of(p);
    let mut slots: Vec<Slot> = Vec::with_capacity(capacity);
    // The stones in the world this step (a buffer kept across steps: no allocation per step).
    let mut in_world: Vec<(RigidBodyHandle, ColliderHandle)> = Vec::with_capacity(capacity);
    let mut queue = queue.fuse();
    loop {
        while slots.len() < capacity {
            let Some((index, release)) = queue.next() else { break };
            let z0 = release_height(stone, p, &release);
            let free = FreeBody::new(z0, release.linvel, release.orientation, &release.angvel);
            let place = if free_flight {
                land_if_due(&mut world, &stone.body, p, free)
            } else {
                enter_world(&mut world, &stone.body, p, &free)
            };
            slots.push(Slot { index, place, progress: Progress::new(p, 0, RestKind::Speeds) });
        }
        if slots.is_empty() {
            return;
        }
        in_world.clear();
        in_world.extend(slots.iter().filter_map(|s| match s.place {
            Place::World { handle, collider } => Some((handle, collider)),
            Place::Air(_) => None,
        }));
        if !in_world.is_empty() {
            step_world(&mut world, &law, &stone.body, ground_collider, &in_world);
        }
        let mut k = 0;
        while k < slots.len() {
            let s = &mut slots[k];
            let state = match &mut s.place {
                Place::World { handle, .. } => body_state(&world.bodies[*handle], &stone.body),
                Place::Air(b) => {
                    b.step(p.dt, &inertia, &inertia_inv);
                    air_state(b, &stone.body)
                }
            };
            // The ground never moves here and the speed rule reads no position.
            let sample = RestSample { state: &state, ground_velocity: Vec3::zeros(), offset: Vec3::zeros() };
            match s.progress.after_step(&sample, cert) {
                None => {
                    if free_flight {
                        s.place = match s.place {
                            Place::World { handle, collider } => {
                                take_off_if_clear(&mut world, &stone.body, handle, collider, ground_collider, &state)
                            }
                            Place::Air(b) => land_if_due(&mut world, &stone.body, p, b),
                        };
                    }
                    k += 1;
                }
                Some(end) => {
                    let s = slots.swap_remove(k);
                    if let Place::World { handle, .. } = s.place {
                        world.remove_body(handle);
                    }
                    on_done(outcome(stone, p, &end, s.index));
                }
            }
        }
    }
}

/// Insert the stone in the state `b` into the world.
fn enter_world(world: &mut PhysicsWorld, body: &Body, p: &DropParams, b: &FreeBody) -> Place {
    let (handle, collider) = insert_stone(world, body, p, &b.orientation, b.z, &b.linvel, &b.angvel());
    Place::World { handle, collider }
}

/// Keep `b` in the air while it is clear of the ground ([`flight::in_flight`]); else insert it.
fn land_if_due(world: &mut PhysicsWorld, body: &Body, p: &DropParams, b: FreeBody) -> Place {
    // h ≤ 1 (R_max) in every direction: high up, no support query is needed.
    let clear = flight::in_flight(b.z - 1.0, false) || {
        let down = b.orientation.inverse() * -Vec3::z();
        flight::in_flight(flight::clearance(b.z, body.support_climb(&down)), false)
    };
    if clear {
        Place::Air(b)
    } else {
        enter_world(world, body, p, &b)
    }
}

/// Take the stone out of the world into free flight if the ground gave it no impulse in the
/// last step and it ended clear of the ground ([`flight::in_flight`]).
fn take_off_if_clear(
    world: &mut PhysicsWorld,
    body: &Body,
    handle: RigidBodyHandle,
    collider: ColliderHandle,
    ground: ColliderHandle,
    state: &BodyState,
) -> Place {
    let clear = flight::in_flight(flight::clearance(state.z, body.support_climb(&state.down)), true);
    if clear && normal_impulse(world, ground, collider) == 0.0 {
        let rb = &world.bodies[handle];
        let q = super::convert::quat_back(rb.rotation());
        let b = FreeBody::new(state.z, state.linvel, q, &state.angvel);
        world.remove_body(handle);
        Place::Air(b)
    } else {
        Place::World { handle, collider }
    }
}

/// The state of a stone in free flight (as [`body_state`] reads it off a rapier body).
fn air_state(b: &FreeBody, body: &Body) -> BodyState {
    let down = b.orientation.inverse() * -Vec3::z();
    let level = b.z + b.kinetic_energy(&body.inertia) / GRAVITY;
    BodyState { down, z: b.z, linvel: b.linvel, angvel: b.angvel(), level }
}
