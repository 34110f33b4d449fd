"""MuJoCo side of `experiments/drops_vs_mujoco.rs`: the same drops as the project's, in MuJoCo.

Usage: python3 mujoco_drops.py IN.json OUT.json

IN.json (written by the Rust experiment): the physics (release height, friction, restitution,
damping, dt, rest rule, cap), the number of timed drops, the size of the (untimed) sample for the
statistics, whose first drops are the timed ones, how many times to time them, the release
orientation of every drop of the sample (`orientations`: unit quaternions (w, x, y, z), project
body frame → world, the project's own releases of the same drop indices, so that both engines
drop the same stones drop by drop), and the bodies, each with its hull corners relative to G and
its inertia tensor about G, in the scaled frame of the project (R_max = 1 m, mass 1, g = 9.81).

OUT.json: the MuJoCo settings chosen, the measured restitution of a ball drop, and per body the
final body-frame down direction of every drop (in the project's body frame), its steps, whether
it came to rest and how many warnings MuJoCo raised during it (a bad qacc, qvel or qpos is an
instability, after which MuJoCo resets the state), for the timed drops and for the whole sample,
with the CPU time of the timed drops. The project classifies the down directions with its own
rule (`Stone::rest`), so both engines are counted by the same rule.

How the physics is matched (the README of `results/drops_vs_mujoco/` says the same):

* body: a mesh geom on the hull corners (MuJoCo collides with their convex hull) and an explicit
  `<inertial>` of mass 1 with the project's inertia tensor. The corners are first rotated into
  the principal axes of that tensor (so `fullinertia` is diagonal there), because MuJoCo's
  damping is per degree of freedom: with the body frame on the principal axes, a rotational
  damping of dof_damping = k I_i on each axis is the torque -k I ω, i.e. a uniform angular
  damping k (rad/s per s), as rapier's. Down directions are rotated back before output.
* release: the project's release orientation of the same drop index (IN.json `orientations`),
  carried over to the principal frame (`principal_orientation`), from rest, the lowest corner
  `height` above the plane: the two engines drop the same stone in the same pose, so their
  outcomes are compared drop by drop, not only as two samples.
* global damping: dof_damping = (c_lin · m, c_lin · m, c_lin · m, c_ang I_1, c_ang I_2, c_ang I_3)
  on the free joint; with an integrator that treats damping implicitly (implicitfast, or Euler),
  one step divides the velocity by (1 + dt c), which is exactly rapier's damping law.
* contact: condim 3 (sliding friction only: no torsional or rolling friction, which the project
  side switches off too), friction 0.6 on both geoms, the elliptic friction cone (the Coulomb
  cone; MuJoCo's default is the pyramidal one), MuJoCo's default solimp and timeconst 0.02 s
  with a damping ratio chosen by bisection so that a ball dropped on the plane rebounds with the
  target restitution (MuJoCo has no restitution coefficient: a bounce is the soft contact's
  under-damped spring), or the solref given in IN.json (`solref`, e.g. the one calibrated at
  another step: the same model at another step), whose ball restitution is then measured.
* numerics: opt.timestep = dt, the implicitfast integrator (MuJoCo's default is Euler), the
  default Newton solver (100 iterations, tolerance 1e-8), one thread.
* rest: the project's rule: linear speed of G < rest_linear_speed and angular speed <
  rest_angular_speed for ceil(rest_time / dt) consecutive steps, checked after every step; the
  cap is ceil(max_time / dt) steps.

Timing: the CPU time of this process (`time.process_time`, one thread) over the Python loop of
`mj_step` plus the rest check of every drop (`loop`), and, since MuJoCo is deterministic, over
the same drops replayed as one `mj_step(m, d, nstep=steps)` call each (`replay`: the stepping
alone, without the Python interpreter per step). The replay's final state is checked to be the
loop's, bit for bit.
"""

import json
import math
import sys
import time

import mujoco
import numpy as np

TIMECONST = 0.02  # MuJoCo's default contact time constant (s)


def contact_xml(mu, solref):
    """The contact attributes of both geoms (MuJoCo combines them; equal values stay as given)."""
    return f'condim="3" friction="{float(mu)!r} 0 0" solref="{float(solref[0])!r} {float(solref[1])!r}"'


def model_xml(p, corners_principal, principal_inertia, solref, integrator):
    """A plane floor and one free body with a mesh geom on `corners_principal`."""
    contact = contact_xml(p["friction"], solref)
    verts = " ".join(repr(float(x)) for c in corners_principal for x in c)
    i1, i2, i3 = (repr(float(x)) for x in principal_inertia)
    return f"""<mujoco model="drop">
  <option timestep="{p['dt']!r}" gravity="0 0 -9.81" integrator="{integrator}" cone="elliptic"/>
  <asset><mesh name="hull" vertex="{verts}"/></asset>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 1" {contact}/>
    <body name="stone" pos="0 0 2">
      <freejoint name="free"/>
      <inertial pos="0 0 0" mass="1" fullinertia="{i1} {i2} {i3} 0 0 0"/>
      <geom name="hull" type="mesh" mesh="hull" {contact}/>
    </body>
  </worldbody>
</mujoco>"""


def ball_xml(p, solref, integrator):
    contact = contact_xml(p["friction"], solref)
    return f"""<mujoco model="ball">
  <option timestep="{p['dt']!r}" gravity="0 0 -9.81" integrator="{integrator}" cone="elliptic"/>
  <worldbody>
    <geom type="plane" size="0 0 1" {contact}/>
    <body pos="0 0 {1.0 + p['height']!r}">
      <freejoint/>
      <inertial pos="0 0 0" mass="1" diaginertia="0.4 0.4 0.4"/>
      <geom type="sphere" size="1" {contact}/>
    </body>
  </worldbody>
</mujoco>"""


def rebound(m, d, contact_height, height):
    """Drop the body of (m, d) as placed: its restitution from the first rebound, measured by
    energy, e = sqrt(rebound height / drop height) with heights of G above where it first
    touches (`contact_height`), and by speeds, rebound over impact speed at the steps where the
    contact starts and stops penetrating. (0, 0) if it never leaves the ground."""
    v_in = v_out = None
    apex = -math.inf
    for _ in range(int(10.0 / m.opt.timestep)):
        before = float(d.qvel[2])
        mujoco.mj_step(m, d)
        touching = any(d.contact[i].dist < 0 for i in range(d.ncon))
        if v_in is None:
            if touching:
                v_in = before
        elif v_out is None:
            if not touching:
                v_out = float(d.qvel[2])
        elif touching or d.qvel[2] < 0:
            up = max(apex - contact_height, 0.0)
            return math.sqrt(up / height), -v_out / v_in
        else:
            apex = max(apex, float(d.qpos[2]))
    return 0.0, 0.0


def ball_restitution(p, solref, integrator):
    """Restitution (by energy, by speeds) of a ball of radius 1 (= R_max) dropped with its
    lowest point `height` above the plane (see `rebound`)."""
    m = mujoco.MjModel.from_xml_string(ball_xml(p, solref, integrator))
    d = mujoco.MjData(m)
    return rebound(m, d, 1.0, p["height"])


def calibrate(p, integrator):
    """The damping ratio of solref (TIMECONST, ratio) whose ball drop rebounds with e = target
    (by energy, `rebound`), by bisection (e falls as the ratio grows)."""
    target = p["restitution"]
    lo, hi = 0.05, 1.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if ball_restitution(p, (TIMECONST, mid), integrator)[0] > target:
            lo = mid
        else:
            hi = mid
    ratio = 0.5 * (lo + hi)
    return (TIMECONST, ratio), ball_restitution(p, (TIMECONST, ratio), integrator)


def rotation_taking(a, b):
    """A unit quaternion (w, x, y, z) rotating the unit vector a onto the unit vector b."""
    c = float(np.dot(a, b))
    if c < -1.0 + 1e-12:  # opposite: half a turn about any axis normal to a
        axis = np.cross(a, [1.0, 0.0, 0.0])
        if np.linalg.norm(axis) < 1e-6:
            axis = np.cross(a, [0.0, 1.0, 0.0])
        axis /= np.linalg.norm(axis)
        return [0.0, *axis.tolist()]
    q = np.array([1.0 + c, *np.cross(a, b)])
    return (q / np.linalg.norm(q)).tolist()


def quat_matrix(q):
    """The rotation matrix of a unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def principal_orientation(q_project, vecs):
    """The MuJoCo body's orientation (principal frame → world, (w, x, y, z)) of the project's
    release orientation `q_project` (project body frame → world): x_world = R(q) vecs x_principal."""
    q = np.array(q_project, dtype=float)
    out = np.zeros(4)
    mujoco.mju_mat2Quat(out, (quat_matrix(q / np.linalg.norm(q)) @ vecs).flatten())
    return out


def quat_rotate_inverse(q, v):
    """R(q)ᵀ v for a unit quaternion q = (w, x, y, z)."""
    return quat_matrix(q).T @ v


def check_placement(m, d, corners_principal):
    """The compiled mesh must sit where the corners are in the body frame (MuJoCo re-centres a
    mesh on its own centroid and moves the geom to compensate): compare the support in a few
    directions with the corners' own, in the body frame."""
    mujoco.mj_resetData(m, d)
    mujoco.mj_forward(m, d)
    g = m.geom("hull").id
    mesh = m.geom_dataid[g]
    a, n = m.mesh_vertadr[mesh], m.mesh_vertnum[mesh]
    verts = m.mesh_vert[a : a + n].astype(float)
    body = m.body("stone").id
    rb = d.xmat[body].reshape(3, 3)
    rg = d.geom_xmat[g].reshape(3, 3)
    in_body = (rb.T @ (rg @ verts.T + (d.geom_xpos[g] - d.xpos[body])[:, None])).T
    worst = 0.0
    for u in np.eye(3).tolist() + (-np.eye(3)).tolist() + [[0.6, 0.48, 0.64]]:
        u = np.array(u) / np.linalg.norm(u)
        worst = max(worst, abs((in_body @ u).max() - (corners_principal @ u).max()))
    return worst


def run_body(p, body, solref, integrator):
    corners = np.array(body["corners"], dtype=float)
    inertia = np.array(body["inertia"], dtype=float)
    lam, vecs = np.linalg.eigh(0.5 * (inertia + inertia.T))
    if np.linalg.det(vecs) < 0:  # a rotation, not a reflection (which would mirror the stone)
        vecs[:, 2] = -vecs[:, 2]
    # Columns of `vecs`: principal axes in the project's body frame; x_principal = vecsᵀ x.
    principal = corners @ vecs
    m = mujoco.MjModel.from_xml_string(model_xml(p, principal, lam, solref, integrator))
    d = mujoco.MjData(m)
    placement_error = check_placement(m, d, principal)
    m.dof_damping[:3] = p["linear_damping"] * 1.0  # × the mass
    m.dof_damping[3:6] = p["angular_damping"] * lam
    if m.body_mass[m.body("stone").id] != 1.0:
        raise SystemExit("MuJoCo body mass is not 1")

    flat = None
    if body.get("flat_normal") is not None:
        # A flat landing on the facet with this outward normal (project body frame), no damping:
        # the restitution the contact gives this body.
        n = vecs.T @ np.array(body["flat_normal"], dtype=float)
        saved = m.dof_damping.copy()
        m.dof_damping[:] = 0.0
        mujoco.mj_resetData(m, d)
        h = float((principal @ n).max())
        d.qpos[:3] = (0.0, 0.0, p["height"] + h)
        d.qpos[3:7] = rotation_taking(n, np.array([0.0, 0.0, -1.0]))
        flat = rebound(m, d, h, p["height"])
        m.dof_damping[:] = saved

    n = p["drops"]
    total = max(n, p.get("sample_drops", n))
    quats = [principal_orientation(q, vecs) for q in p["orientations"][:total]]
    if len(quats) < total:
        raise SystemExit(f"IN.json gives {len(quats)} orientations for {total} drops")
    down_world = np.array([0.0, 0.0, -1.0])
    starts = []
    for q in quats:
        down_body = quat_rotate_inverse(q, down_world)
        starts.append((q.tolist(), p["height"] + float((principal @ down_body).max())))

    needed = math.ceil(p["rest_time"] / p["dt"])
    cap = math.ceil(p["max_time"] / p["dt"])
    lin2 = p["rest_linear_speed"] ** 2
    ang2 = p["rest_angular_speed"] ** 2
    step = mujoco.mj_step
    qvel = d.qvel

    def warnings():
        """Warnings MuJoCo raised since the last reset (mj_resetData clears them)."""
        return int(sum(w.number for w in d.warning))

    def drop(q, z):
        mujoco.mj_resetData(m, d)
        d.qpos[:3] = (0.0, 0.0, z)
        d.qpos[3:7] = q
        calm = 0
        steps = 0
        while steps < cap:
            step(m, d)
            steps += 1
            vx, vy, vz, wx, wy, wz = qvel.tolist()
            if vx * vx + vy * vy + vz * vz < lin2 and wx * wx + wy * wy + wz * wz < ang2:
                calm += 1
                if calm >= needed:
                    return steps, True
            else:
                calm = 0
        return steps, False

    loop_times = []
    results = None
    for _ in range(p["repeats"]):
        out = []
        t = time.process_time()
        for q, z in starts[:n]:
            steps, settled = drop(q, z)
            out.append((steps, settled, d.qpos.copy(), d.xmat[1].copy(), warnings()))
        loop_times.append(time.process_time() - t)
        if results is None:
            results = out
        elif any(not np.array_equal(a[2], b[2]) for a, b in zip(results, out)):
            raise SystemExit("MuJoCo drops differ between two repeats")

    # The same drops as one C loop each: the stepping alone.
    replay_times = []
    deterministic = True
    for _ in range(p["repeats"]):
        t = time.process_time()
        finals = []
        for (q, z), (steps, *_) in zip(starts[:n], results):
            mujoco.mj_resetData(m, d)
            d.qpos[:3] = (0.0, 0.0, z)
            d.qpos[3:7] = q
            step(m, d, nstep=steps)
            finals.append(d.qpos.copy())
        replay_times.append(time.process_time() - t)
        deterministic &= all(np.array_equal(f, r[2]) for f, r in zip(finals, results))

    # The larger sample for the statistics (untimed): the timed drops and the rest of the stream.
    sample = list(results)
    for q, z in starts[n:]:
        steps, settled = drop(q, z)
        sample.append((steps, settled, None, d.xmat[1].copy(), warnings()))

    def record(steps, settled, xmat, warned):
        r = xmat.reshape(3, 3)  # body → world, principal frame
        down = vecs @ (r.T @ down_world)
        return {"down": down.tolist(), "steps": steps, "settled": bool(settled), "warnings": warned}

    drops = [record(steps, settled, xmat, w) for steps, settled, _, xmat, w in results]
    sample_drops = [record(steps, settled, xmat, w) for steps, settled, _, xmat, w in sample]
    return {
        "name": body["name"],
        "principal_inertia": lam.tolist(),
        "placement_error": placement_error,
        "mesh_vertices": int(m.mesh_vertnum[0]),
        "flat_restitution": flat,
        "drops": drops,
        "sample_drops": sample_drops,
        "loop_cpu_s": loop_times,
        "replay_cpu_s": replay_times,
        "replay_identical": bool(deterministic),
        # Every release's initial down direction, back in the project's body frame: the Rust side
        # checks it against its own release of the same drop index.
        "release_downs": [(vecs @ quat_rotate_inverse(q, down_world)).tolist() for q, _ in starts],
        "steps_total": int(sum(r[0] for r in results)),
    }


def main():
    if len(sys.argv) != 3:
        raise SystemExit("usage: mujoco_drops.py IN.json OUT.json")
    with open(sys.argv[1]) as f:
        p = json.load(f)
    integrator = "implicitfast" if hasattr(mujoco.mjtIntegrator, "mjINT_IMPLICITFAST") else "Euler"
    if p.get("solref") is not None:
        solref = (float(p["solref"][0]), float(p["solref"][1]))
        e, e_speeds = ball_restitution(p, solref, integrator)
    else:
        solref, (e, e_speeds) = calibrate(p, integrator)
    how = "given" if p.get("solref") is not None else "calibrated"
    print(
        f"MuJoCo {mujoco.__version__}: dt {p['dt']}, integrator {integrator}, elliptic cone, condim 3, "
        f"{how} solref ({solref[0]}, {solref[1]:.4f}): ball restitution e = {e:.4f} by rebound height, "
        f"{e_speeds:.4f} by speeds at the steps contact starts/ends (target {p['restitution']})",
        file=sys.stderr,
    )
    bodies = []
    for body in p["bodies"]:
        r = run_body(p, body, solref, integrator)
        best = min(r["loop_cpu_s"])
        print(
            f"  {r['name']}: {len(r['drops']) / best:.1f} drops/s (Python loop), "
            f"{len(r['drops']) / min(r['replay_cpu_s']):.1f} drops/s (stepping alone)",
            file=sys.stderr,
        )
        bodies.append(r)
    m = mujoco.MjModel.from_xml_string("<mujoco/>")
    out = {
        "mujoco_version": mujoco.__version__,
        "numpy_version": np.__version__,
        "python_version": sys.version.split()[0],
        "integrator": integrator,
        "default_integrator": mujoco.mjtIntegrator(m.opt.integrator).name,
        "cone": "elliptic",
        "solver": mujoco.mjtSolver(m.opt.solver).name,
        "iterations": int(m.opt.iterations),
        "tolerance": float(m.opt.tolerance),
        "solref": list(solref),
        "solref_calibrated": p.get("solref") is None,
        "solimp": [float(x) for x in mujoco.MjModel.from_xml_string(ball_xml(p, solref, integrator)).geom_solimp[0]],
        "ball_restitution": e,
        "ball_restitution_speeds": e_speeds,
        "bodies": bodies,
    }
    with open(sys.argv[2], "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
