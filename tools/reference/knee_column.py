#!/usr/bin/env python3
"""Independent high-accuracy reference solution of the knee-column benchmark.

Implements the RFE model of /work/shared/SPEC.md straight from the text of
section 1 (Model) and section 4 (knee-column benchmark), with numpy/scipy only.
It is a test fixture for the Rust crate `rfeid`; it deliberately shares no
code with it.

Usage
-----
    python3 tools/reference/knee_column.py [OUT.csv] [--no-check]

Writes OUT.csv (if given) with header `time,knee_ax,knee_ay,knee_az`,
3000 rows (t_k = k / 10000, k = 0..2999), SI units (m/s^2), every value
printed with repr() (shortest round-trip representation, <= 17 significant
digits). Unless --no-check is given it also
  * repeats the integration at a looser tolerance and prints the relative
    RMS difference per sensor (convergence check),
  * cross-checks against an implicit Radau integration,
  * prints RMS of each signal and the range of the instantaneous
    tangent-stiffness natural frequencies along the trajectory.

Integration scheme
------------------
DOP853 (scipy) is stepped *exactly* onto every sample instant t_k (the
solver is restarted at each sample with the last accepted step size as its
first step), so sample values are step end points, not dense-output
interpolants. Accelerations at the samples are evaluated from the state via
the equation of motion q'' = M^-1 (P(t) - B^T f(Bq, Bq')).
"""

import sys
import time

import numpy as np
from scipy.integrate import DOP853, Radau, solve_ivp

# ---------------------------------------------------------------------------
# Units (SPEC section 4: paper's units converted to SI)
# ---------------------------------------------------------------------------
daN = 10.0            # N
um = 1e-6             # m
ms = 1e-3             # s
A_N = daN / um**2     # daN/um^2        -> N/m^2   (x 1e13)
A_T = daN / um        # daN/um          -> N/m     (x 1e7)
H = daN * ms / um     # daN*ms/um       -> N*s/m   (x 1e4)

# ---------------------------------------------------------------------------
# Bodies (SPEC section 4 table). Principal axes = global axes, so R_b = I.
# Generalized coordinates per body: q_b = [u1 u2 u3 phi1 phi2 phi3].
# Global coordinate vector q (12) = [q_column (0..5), q_knee (6..11)].
# ---------------------------------------------------------------------------
BODIES = {
    "column": dict(mass=900.0, inertia=(219.0, 210.75, 45.75),
                   com=np.array([0.0, 0.0, 0.80]), R=np.eye(3)),
    "knee":   dict(mass=320.0, inertia=(18.47, 10.8, 18.47),
                   com=np.array([0.0, 0.65, 0.75]), R=np.eye(3)),
}
BODY_INDEX = {"column": 0, "knee": 1}   # 'ground' has no coordinates
NQ = 6 * len(BODY_INDEX)

# M = diag(m, m, m, J1, J2, J3) per body
M_DIAG = np.concatenate([
    [BODIES[b]["mass"]] * 3 + list(BODIES[b]["inertia"])
    for b in ("column", "knee")
])
M_INV = 1.0 / M_DIAG

# ---------------------------------------------------------------------------
# Parameters at their "true" values (SPEC section 4, Tables 1-2)
# ---------------------------------------------------------------------------
a_n = np.array([380.0, 370.0, 340.0, 660.0]) * A_N
a_t = np.array([15.0, 15.0, 13.0, 27.0]) * A_T
h_n = np.array([3.6, 3.5, 2.7, 2.1]) * H
h_t = np.array([5.5, 5.5, 0.21, 7.7]) * H

s2 = np.sqrt(2.0)
GLOBAL_AXES = [np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 1.0])]

# Element list. Each element: body r, to p, point x, axes [e1,e2,e3], and a
# dict of present translational components:
#   comp index (0=ux,1=uy,2=uz) -> (law, stiffness-or-a, damping c)
# No rotational components are present anywhere in this benchmark.
ELEMENTS = []
SLIDEWAYS = [  # SDE 1..4: (at, e1 normal, e2, e3)
    ((-0.20, 0.30, 0.95), (0, 1, 0), (0, 0, 1), (1, 0, 0)),
    ((0.20, 0.30, 0.62), (0, 1, 0), (0, 0, 1), (1, 0, 0)),
    ((-0.26, 0.24, 0.70), (1 / s2, 1 / s2, 0), (0, 0, 1), (1 / s2, -1 / s2, 0)),
    ((0.26, 0.24, 0.88), (-1 / s2, 1 / s2, 0), (0, 0, 1), (1 / s2, 1 / s2, 0)),
]
for i, (at, e1, e2, e3) in enumerate(SLIDEWAYS):
    ELEMENTS.append(dict(
        name=f"slide{i + 1}", body="knee", to="column", at=np.array(at, float),
        axes=[np.array(e1, float), np.array(e2, float), np.array(e3, float)],
        comps={0: ("power", a_n[i], h_n[i]),     # ux: normal, power law m=2
               1: ("linear", a_t[i], h_t[i]),    # uy: tangential, linear
               2: ("linear", a_t[i], h_t[i])}))  # uz: tangential, linear
# SDE 5: ball screw knee -> column, global axes, uz only
ELEMENTS.append(dict(
    name="screw", body="knee", to="column", at=np.array([0.0, 0.50, 0.50]),
    axes=GLOBAL_AXES, comps={2: ("linear", 2.0e8, 2.0e3)}))
# SDE 6..9: isolation pads column -> ground at (+-0.35, +-0.45, 0)
for sx in (-1.0, 1.0):
    for sy in (-1.0, 1.0):
        ELEMENTS.append(dict(
            name=f"pad({sx:+.0f},{sy:+.0f})", body="column", to="ground",
            at=np.array([0.35 * sx, 0.45 * sy, 0.0]), axes=GLOBAL_AXES,
            comps={0: ("linear", 2.0e7, 4.0e3),
                   1: ("linear", 2.0e7, 4.0e3),
                   2: ("linear", 6.0e7, 8.0e3)}))

POWER_M = 2.0   # joint exponent of the power law (SPEC section 4: m = 2)


def cross_matrix(v):
    """[v]x such that [v]x w = v x w."""
    return np.array([[0.0, -v[2], v[1]],
                     [v[2], 0.0, -v[0]],
                     [-v[1], v[0], 0.0]])


def S_matrix(rho):
    """S(rho) = [[I, -[rho]x], [0, I]] (6x6), so that w = S(rho) q_b."""
    S = np.eye(6)
    S[0:3, 3:6] = -cross_matrix(rho)
    return S


def rho_of(body, x):
    """Body-frame offset rho = R_b^T (x - c_b) of global point x."""
    b = BODIES[body]
    return b["R"].T @ (x - b["com"])


def element_block(elem, body):
    """Theta_b S(rho_b) (6x6) for an element and one of its bodies (eq. 5)."""
    E = np.column_stack(elem["axes"])          # columns = element axes
    theta = E.T @ BODIES[body]["R"]            # theta_b = E^T R_b
    Theta = np.zeros((6, 6))
    Theta[0:3, 0:3] = theta
    Theta[3:6, 3:6] = theta
    return Theta @ S_matrix(rho_of(body, elem["at"]))


def build_B():
    """Stack one row per present component: delta = B q.

    delta = Theta_r S(rho_r) q_r - Theta_p S(rho_p) q_p  (SPEC eq. 5).
    Returns B (n_comp x 12) and per-component arrays:
      is_power (bool), coef (k for linear, a for power), damp (c).
    """
    rows, is_power, coef, damp, names = [], [], [], [], []
    for elem in ELEMENTS:
        blk_r = element_block(elem, elem["body"])
        blk_p = None if elem["to"] == "ground" else element_block(elem, elem["to"])
        for ci in sorted(elem["comps"]):
            law, k, c = elem["comps"][ci]
            row = np.zeros(NQ)
            r = BODY_INDEX[elem["body"]]
            row[6 * r:6 * r + 6] += blk_r[ci]
            if blk_p is not None:
                p = BODY_INDEX[elem["to"]]
                row[6 * p:6 * p + 6] -= blk_p[ci]
            rows.append(row)
            is_power.append(law == "power")
            coef.append(k)
            damp.append(c)
            names.append(f"{elem['name']}.{'xyz'[ci]}")
    return (np.array(rows), np.array(is_power), np.array(coef),
            np.array(damp), names)


B, IS_POWER, COEF, DAMP, COMP_NAMES = build_B()
BT = B.T.copy()
assert B.shape == (25, 12)

# ---------------------------------------------------------------------------
# Excitation: force P(t) d at x on knee, equal and opposite on column.
# Generalized force on body b: +-S(rho_b)^T [R_b^T d; 0] P(t)
# ---------------------------------------------------------------------------
EXC_AT = np.array([0.12, 0.45, 0.85])
EXC_DIR = np.array([1.0, 2.0, 1.0]) / np.linalg.norm([1.0, 2.0, 1.0])
EXC_AMP = 1000.0      # N (P0 = 100 daN)
EXC_FREQ = 80.0       # Hz


def excitation_vector():
    g = np.zeros(NQ)
    for body, sign in (("knee", +1.0), ("column", -1.0)):
        R = BODIES[body]["R"]
        rho = rho_of(body, EXC_AT)
        gb = S_matrix(rho).T @ np.concatenate([R.T @ EXC_DIR, np.zeros(3)])
        i = BODY_INDEX[body]
        g[6 * i:6 * i + 6] += sign * gb
    return g


G_EXC = excitation_vector()   # P-vector per newton of P(t)


def P_of_t(t):
    return EXC_AMP * np.sin(2.0 * np.pi * EXC_FREQ * t)


# ---------------------------------------------------------------------------
# Equation of motion  M q'' + B^T f(Bq, Bq') = P(t)
# ---------------------------------------------------------------------------
def component_forces(delta, delta_dot):
    """f_i = law_i(delta_i) + c_i delta_dot_i.

    linear: k delta;  power: a sign(delta) |delta|^m  (m = 2)."""
    law = np.where(IS_POWER,
                   COEF * np.sign(delta) * np.abs(delta) ** POWER_M,
                   COEF * delta)
    return law + DAMP * delta_dot


def acceleration(t, q, v):
    f = component_forces(B @ q, B @ v)
    return M_INV * (G_EXC * P_of_t(t) - BT @ f)


NFEV = [0]


def rhs(t, y):
    NFEV[0] += 1
    q = y[:NQ]
    v = y[NQ:]
    return np.concatenate([v, acceleration(t, q, v)])


# ---------------------------------------------------------------------------
# Sensors: acceleration of knee centre of mass along global X, Y, Z.
# y = n . R_b (u'' + phi'' x rho), rho = 0, R_b = I  ->  knee u'' components.
# ---------------------------------------------------------------------------
SENSOR_NAMES = ["knee_ax", "knee_ay", "knee_az"]
SENSOR_DIRS = np.eye(3)


def sensors_from_state(t, y):
    a = acceleration(t, y[:NQ], y[NQ:])
    k = BODY_INDEX["knee"]
    R = BODIES["knee"]["R"]
    rho = rho_of("knee", BODIES["knee"]["com"])      # = 0
    acc_point = R @ (a[6 * k:6 * k + 3] + np.cross(a[6 * k + 3:6 * k + 6], rho))
    return SENSOR_DIRS @ acc_point


# ---------------------------------------------------------------------------
# Sampling
# ---------------------------------------------------------------------------
DURATION = 0.3
RATE = 10000.0
N_SAMPLES = int(round(DURATION * RATE))
T_SAMPLES = np.arange(N_SAMPLES) / RATE          # t_k = k / rate

# Per-component absolute-tolerance scales: characteristic magnitudes of the
# state (displacements ~1e-7 m / rotations ~1e-7 rad, velocities ~1e-4 m/s /
# rad/s; the measured maxima are printed below). atol_i = rtol * scale_i, so
# the error control is effectively relative to each component's magnitude.
SCALE = np.concatenate([np.full(NQ, 1e-7), np.full(NQ, 1e-4)])


def simulate_dop853(rtol, atol_factor=1.0):
    """DOP853 stepped exactly onto every sample instant. Returns (Y, nfev)."""
    atol = atol_factor * rtol * SCALE
    y = np.zeros(2 * NQ)
    Y = np.empty((N_SAMPLES, 2 * NQ))
    Y[0] = y
    NFEV[0] = 0
    h = None
    nsteps = 0
    for k in range(1, N_SAMPLES):
        kwargs = dict(rtol=rtol, atol=atol)
        if h is not None:
            kwargs["first_step"] = min(h, T_SAMPLES[k] - T_SAMPLES[k - 1])
        solver = DOP853(rhs, T_SAMPLES[k - 1], y, T_SAMPLES[k], **kwargs)
        while solver.status == "running":
            msg = solver.step()
            if msg is not None:
                raise RuntimeError(msg)
            nsteps += 1
            h = solver.h_abs       # step size proposed for the next step
        y = solver.y.copy()
        Y[k] = y
    return Y, NFEV[0], nsteps


def simulate_radau(rtol, atol_factor=1.0):
    """Implicit Radau IIA (order 5) with dense output at the sample instants."""
    atol = atol_factor * rtol * SCALE
    NFEV[0] = 0

    def jac(t, y):
        q, v = y[:NQ], y[NQ:]
        d = B @ q
        kt = np.where(IS_POWER, COEF * POWER_M * np.abs(d) ** (POWER_M - 1), COEF)
        K = BT @ (kt[:, None] * B)
        C = BT @ (DAMP[:, None] * B)
        J = np.zeros((2 * NQ, 2 * NQ))
        J[:NQ, NQ:] = np.eye(NQ)
        J[NQ:, :NQ] = -M_INV[:, None] * K
        J[NQ:, NQ:] = -M_INV[:, None] * C
        return J

    sol = solve_ivp(rhs, (0.0, T_SAMPLES[-1]), np.zeros(2 * NQ), method="Radau",
                    t_eval=T_SAMPLES, rtol=rtol, atol=atol, jac=jac)
    if not sol.success:
        raise RuntimeError(sol.message)
    return sol.y.T, NFEV[0], sol.t.size


def sensor_matrix(Y):
    return np.array([sensors_from_state(t, y) for t, y in zip(T_SAMPLES, Y)])


def rms(x, axis=0):
    return np.sqrt(np.mean(x ** 2, axis=axis))


def rel_rms_diff(A, Bm):
    return rms(A - Bm) / rms(Bm)


def tangent_frequencies(y):
    """Undamped natural frequencies (Hz) of the tangent stiffness at state y:
    K_t = B^T diag(dlaw/ddelta) B, with dlaw/ddelta = k or m a |delta|^(m-1)."""
    d = B @ y[:NQ]
    kt = np.where(IS_POWER, COEF * POWER_M * np.abs(d) ** (POWER_M - 1), COEF)
    K = BT @ (kt[:, None] * B)
    Mh = 1.0 / np.sqrt(M_DIAG)
    A = Mh[:, None] * K * Mh[None, :]
    w2 = np.linalg.eigvalsh(0.5 * (A + A.T))
    return np.sqrt(np.clip(w2, 0.0, None)) / (2.0 * np.pi)


def write_csv(path, Ysens):
    with open(path, "w") as fh:
        fh.write("time," + ",".join(SENSOR_NAMES) + "\n")
        for t, row in zip(T_SAMPLES, Ysens):
            fh.write(",".join(repr(float(v)) for v in (t, *row)) + "\n")


def main(argv):
    out = None
    check = True
    for a in argv[1:]:
        if a == "--no-check":
            check = False
        else:
            out = a

    RTOL_REF = 1e-13
    t0 = time.perf_counter()
    Y, nfev, nsteps = simulate_dop853(RTOL_REF)
    dt = time.perf_counter() - t0
    Ys = sensor_matrix(Y)
    print(f"reference: DOP853 rtol={RTOL_REF:g} atol=rtol*scale "
          f"(scale 1e-7 for q, 1e-4 for q'): {dt:.1f} s, "
          f"{nfev} RHS evals, {nsteps} steps")
    print("max |q| column/knee  :", np.abs(Y[:, :NQ]).max(axis=0))
    print("max |q'| column/knee :", np.abs(Y[:, NQ:]).max(axis=0))
    print("RMS of sensors (m/s^2):",
          dict(zip(SENSOR_NAMES, rms(Ys).tolist())))
    dmax = np.abs(Y[:, :NQ] @ B.T).max(axis=0)
    print("max |delta| per component (m):")
    for n, v in zip(COMP_NAMES, dmax):
        print(f"  {n:14s} {v:.3e}")

    if out is not None:
        write_csv(out, Ys)
        print(f"wrote {out} ({N_SAMPLES} rows)")

    if not check:
        return

    for rtol, fac in ((1e-12, 1.0), (1e-11, 1.0), (1e-13, 0.1)):
        t0 = time.perf_counter()
        Y2, nfev2, nsteps2 = simulate_dop853(rtol, fac)
        dt2 = time.perf_counter() - t0
        d = rel_rms_diff(sensor_matrix(Y2), Ys)
        print(f"DOP853 rtol={rtol:g} atol=rtol*scale*{fac:g}: {dt2:.1f} s, "
              f"{nfev2} RHS evals, {nsteps2} steps; rel RMS diff vs reference:",
              dict(zip(SENSOR_NAMES, d.tolist())))

    for rtol in (1e-10, 1e-11):
        t0 = time.perf_counter()
        Y3, nfev3, _ = simulate_radau(rtol)
        dt3 = time.perf_counter() - t0
        d = rel_rms_diff(sensor_matrix(Y3), Ys)
        print(f"Radau rtol={rtol:g} atol=rtol*scale: {dt3:.1f} s, {nfev3} RHS "
              f"evals; rel RMS diff vs reference:",
              dict(zip(SENSOR_NAMES, d.tolist())))

    # Tangent-stiffness natural frequencies along the trajectory
    lo_all, hi_all = [], []
    for k in range(1, N_SAMPLES, 1):
        f = tangent_frequencies(Y[k])
        lo_all.append(f[0])
        hi_all.append(f[-1])
    lo_all, hi_all = np.array(lo_all), np.array(hi_all)
    print("tangent-stiffness natural frequencies over samples k=1..2999:")
    print(f"  lowest mode:  min {lo_all.min():.1f} Hz, max {lo_all.max():.1f} Hz")
    print(f"  highest mode: min {hi_all.min():.1f} Hz, max {hi_all.max():.1f} Hz")
    for k in (300, 1000, 2000, 2999):
        print(f"  t={T_SAMPLES[k]:.4f} s:",
              np.array2string(tangent_frequencies(Y[k]), precision=1))


if __name__ == "__main__":
    main(sys.argv)
