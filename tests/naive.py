"""Slow, obvious NumPy twins of the compiled kernels. The fast kernels must match them.

Written independently of brakeca._kernels: 2-D arrays, direct evaluation of the friction force,
plain Python loops for the rules. The between-stop steps are here too: the fibre field's
exposure after a stop (:func:`expose`, cell by cell, against brakeca.automaton's vectorised
``expose_buried_fibres``); rule S is written out in tests/verification/test_kernel_vs_naive.py.
Nothing is imported from brakeca.
"""

from __future__ import annotations

import numpy as np


def friction_force(h, area, z, K, mu0, c, mumin):
    p = K * np.maximum(h - z, 0.0)
    return float(np.sum(np.maximum(mumin, mu0 - c * p) * p * area))


def first_root(h, area, K, mu0, c, mumin, target):
    """First z (from the top down) where the friction force reaches target: scan the
    breakpoints, fit the exact quadratic on each interval through three direct evaluations."""
    uf = (mu0 - mumin) / (c * K) if c > 0 else np.inf
    bps = np.concatenate([h, h - uf])
    bps = np.unique(bps[np.isfinite(bps)])[::-1]
    total_area = float(np.sum(area))
    for n, hi in enumerate(bps):
        if n + 1 < len(bps):
            lo = bps[n + 1]
        else:  # below every breakpoint F grows linearly (every cell on the floor branch)
            lo = hi - 2.0 * target / (K * min(mumin, mu0) * total_area) - 1e-6
        f0 = friction_force(h, area, hi, K, mu0, c, mumin)
        fm = friction_force(h, area, 0.5 * (hi + lo), K, mu0, c, mumin)
        f1 = friction_force(h, area, lo, K, mu0, c, mumin)
        # F(t) = f0 + b t + a t^2 on t in [0, 1], z = hi + t (lo - hi)
        b = -3 * f0 + 4 * fm - f1
        a = 2 * f0 - 4 * fm + 2 * f1
        if abs(a) > 1e-300:
            roots = np.roots([a, b, f0 - target])
        elif b != 0.0:
            roots = np.array([(target - f0) / b])
        else:  # F constant on a round-off-sized interval: no crossing inside it
            continue
        ts = sorted(
            float(r.real)
            for r in np.atleast_1d(roots)
            if abs(r.imag) < 1e-12 and -1e-12 <= r.real <= 1 + 1e-12
        )
        if ts:
            return hi + max(ts[0], 0.0) * (lo - hi)
    raise RuntimeError("no root")


def step(state, params, target, frac):
    """One time step on 2-D arrays; returns a dict of per-step figures. Mutates state."""
    H, B, S, FF, inflow = state["H"], state["B"], state["S"], state["FF"], state["inflow"]
    A, slide = params["area_row"], params["slide_row"]
    K, mu0, c, mumin = params["K"], params["mu0"], params["c"], params["mumin"]
    nr, nt = H.shape
    nsub = params["nsub"]
    nm = nt // nsub
    Acell = np.broadcast_to(A[:, None], H.shape)
    S0 = S.copy()  # statuses at the start of the step
    plate = S0 != 0
    z = first_root(H[plate], Acell[plate], K, mu0, c, mumin, target)
    u = H - z
    contact = plate & (u > 0)
    P = np.where(contact, K * u, 0.0)
    MU = np.maximum(mumin, mu0 - c * P)
    fric = float(np.sum(MU * P * Acell))
    norm = float(np.sum(P * Acell))
    out = np.zeros((nr, nsub))
    removed = 0.0
    for j in range(nr):
        for i in range(nt):
            if not contact[j, i]:
                continue
            dh = min(params["WP"] * P[j, i] * slide[j] * frac, u[j, i])
            if S0[j, i] == 2:
                dh = min(dh, H[j, i] - B[j, i])
            H[j, i] -= dh
            out[j, i // nm] += dh * A[j]
            if S0[j, i] == 1:
                removed += dh * A[j]
    field = state.get("field")  # the fibre field: flat per-cell interval lists, or None
    exposed = []
    for j in range(nr):  # resin cut
        for i in range(nt):
            if S0[j, i] == 0 and H[j, i] > z:
                new = z - params["WR"]
                if field is not None:  # the cut stops at the top of a buried fibre
                    c = j * nt + i
                    k = field["next"][c]
                    reach = k < field["end"][c] and field["top"][k] >= new
                    if reach and field["bottom"][k] < H[j, i]:
                        new = min(H[j, i], field["top"][k])
                        exposed.append((j, i))
                vol = (H[j, i] - new) * A[j]
                H[j, i] = new
                out[j, i // nm] += vol
                removed += vol
    fired = np.zeros(8, dtype=np.int64)  # by rule: [0] fibres exposed, [1..7] the rules
    destroyed = []
    for j in range(nr):
        for i in range(nt):
            if S0[j, i] == 2:
                east = S0[j, i + 1] if i + 1 < nt else 0
                if H[j, i] <= B[j, i]:  # rule 5 (worn through, whatever its east neighbour)
                    destroyed.append((j, i))
                    fired[5] += 1
                elif east == 0:  # rule 4
                    destroyed.append((j, i))
                    fired[4] += 1
            elif S0[j, i] == 1:
                if H[j, i] <= FF[j, i]:  # rule 7
                    destroyed.append((j, i))
                    fired[7] += 1
                elif z - H[j, i] > params["rule6_gap"]:  # rule 6
                    destroyed.append((j, i))
                    fired[6] += 1
    created = []
    exposed_now = set(exposed)
    for j in range(nr):
        for k in range(1, nsub):
            rest = inflow[j, k]
            if rest > 0:
                cols = range(k * nm, (k + 1) * nm)
                if params["east_to_west"]:
                    cols = reversed(cols)
                for i in cols:
                    if (j, i) in exposed_now:  # its fibre stands there now
                        continue
                    if S0[j, i] == 0 and i + 1 < nt and S0[j, i + 1] != 0:
                        cost = (z - H[j, i]) * A[j]
                        if cost <= rest:
                            rest -= cost
                            created.append((j, i))
                            # rules 1, 2, 3: the east plateau and none, one or both diagonals
                            ne = j + 1 < nr and S0[j + 1, i + 1] != 0
                            se = j >= 1 and S0[j - 1, i + 1] != 0
                            fired[1 + int(ne) + int(se)] += 1
            out[j, k] += rest
    for j, i in destroyed:
        if S0[j, i] == 2:
            out[j, i // nm] += (H[j, i] - B[j, i]) * A[j]
            H[j, i] = B[j, i]
        S[j, i] = 0
    for j, i in created:
        B[j, i] = H[j, i]
        H[j, i] = z
        S[j, i] = 2
    for j, i in exposed:  # a primary plateau at the fibre's top, floored at its underside
        c = j * nt + i
        k = field["next"][c]
        B[j, i] = H[j, i]
        FF[j, i] = field["bottom"][k]
        field["next"][c] = k + 1
        S[j, i] = 1
    emitted = float(out[:, -1].sum())
    inflow[:, 1:] = out[:, :-1]
    inflow[:, 0] = 0.0
    state["removed"] += removed
    state["emitted"] += emitted
    held = float(np.sum(np.where(S == 2, (H - B) * Acell, 0.0)))
    ledger = state["removed"] - held - inflow.sum() - state["emitted"]
    return {
        "z": z,
        "friction": fric,
        "normal": norm,
        "cof": fric / norm,
        "pmax": float(P.max()),
        "contact_area": float(np.sum(Acell[contact])),
        "primary_area": float(np.sum(Acell[S == 1])),  # after the step's status changes
        "secondary_area": float(np.sum(Acell[S == 2])),
        "generated": removed,
        "emitted": emitted,
        "held": held,
        "stream": float(inflow.sum()),
        "ledger": ledger,
        "created": len(created),
        "exposed": len(exposed),
        "destroyed": len(destroyed),
        "fired": fired + np.eye(8, dtype=np.int64)[0] * len(exposed),
    }


def expose(S, H, B, FF, area, top, bottom, end, nxt):
    """The fibre field's exposure after a stop, one cell at a time (flat arrays, changed in
    place): a resin or secondary cell whose pad surface (a resin cell's height, a secondary
    plateau's height under its deposit) has come down to or below the top of its next buried
    fibre becomes a primary plateau at that surface, with the fibre's underside as its
    floor; a secondary plateau's deposit is released. Fibres the surface has passed wholly
    are skipped. Returns (exposed, largest lag [m], lag volume [m^3], skipped, released
    [m^3])."""
    exposed = skipped = 0
    max_lag = lag_volume = released = 0.0
    for i in range(S.size):
        if S[i] == 1:
            continue
        surface = B[i] if S[i] == 2 else H[i]
        while nxt[i] < end[i]:
            k = nxt[i]
            if surface > top[k]:  # not reached yet
                break
            if surface > bottom[k]:  # within the fibre: exposed
                if S[i] == 2:
                    released += (H[i] - B[i]) * area[i]
                H[i] = B[i] = surface
                S[i] = 1
                FF[i] = bottom[k]
                nxt[i] = k + 1
                exposed += 1
                max_lag = max(max_lag, top[k] - surface)
                lag_volume += (top[k] - surface) * area[i]
                break
            nxt[i] = k + 1  # passed wholly
            skipped += 1
    return exposed, max_lag, lag_volume, skipped, released
