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

use super::drop::{outcome, release_height, DropOutcome, Release};
use super::params::DropParams;
use super::run::{Certificate, Progress};
use super::stone::Stone;
use super::world::{body_state, ground_world, insert_stone, ContactLaw};
use crate::Vec3;
use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

/// One stone in flight in a batch.
struct Slot {
    index: u64,
    handle: RigidBodyHandle,
    collider: ColliderHandle,
    progress: Progress,
}

/// Simulate the drops of `queue` (drop index and release, in the order given) with at most
/// `capacity` stones in one world at a time, calling `on_done` with each outcome as its drop
/// finishes (in the order they finish). Every outcome equals that of [`super::drop::simulate`]
/// for the same drop (module docs).
pub fn simulate_batch(
    stone: &Stone,
    p: &DropParams,
    cert: &dyn Certificate,
    capacity: usize,
    queue: &mut dyn Iterator<Item = (u64, Release)>,
    on_done: &mut dyn FnMut(DropOutcome),
) {
    let capacity = capacity.max(1);
    let (mut world, _ground, ground_collider) = ground_world(p);
    let law = ContactLaw::of(p);
    let mut slots: Vec<Slot> = Vec::with_capacity(capacity);
    let mut queue = queue.fuse();
    loop {
        while slots.len() < capacity {
            let Some((index, release)) = queue.next() else { break };
            let z0 = release_height(stone, p, &release);
            let (handle, collider) =
                insert_stone(&mut world, &stone.body, p, &release.orientation, z0, &release.linvel, &release.angvel);
            let progress = Progress::new(p, 0);
            slots.push(Slot { index, handle, collider, progress });
        }
        if slots.is_empty() {
            return;
        }
        world.step();
        let mut k = 0;
        while k < slots.len() {
            let s = &mut slots[k];
            if law.acts() {
                law.apply(&mut world, &stone.body, s.handle, s.collider, ground_collider);
            }
            let state = body_state(&world.bodies[s.handle], &stone.body);
            match s.progress.after_step(&state, &Vec3::zeros(), cert) {
                None => k += 1,
                Some(end) => {
                    let s = slots.swap_remove(k);
                    world.remove_body(s.handle);
                    on_done(outcome(stone, p, &end, s.index));
                }
            }
        }
    }
}
