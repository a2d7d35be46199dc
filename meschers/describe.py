"""What a mescher is, in numbers: counts, topology, impossibility, periods (``meschers info``).

One owner for the description the command line prints and the study records for every model.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["describe", "format_info"]


def impossibility_kind(m: Any, order: Any = None) -> str | None:
    """``"zeta"`` (a non-zero period), ``"order"`` (zeta integrates but the depth order cannot
    be realised by the bent embedding: the Window, Escher's cube) or ``None`` (possible)."""
    if order is not None:
        return m.is_impossible(order=order).kind
    return "zeta" if m.is_impossible() else None


def describe(m: Any, order: Any = None) -> dict:
    """Counts, topology, impossibility and periods of a mescher.

    Parameters
    ----------
    m : Mescher
    order : DepthOrder, optional

    Returns
    -------
    dict
        ``vertices``, ``edges``, ``faces``, ``euler_characteristic`` (V - E + F), ``components``,
        ``boundary_loops``, ``genus`` (sum over components of ``(2 - chi_i - b_i) / 2``, the
        surface being orientable), ``impossible``, ``periods``, ``max_integrability_residual``
        and, with an order, ``depth_arcs`` and ``depth_cycles``.
    """
    from meschers_igl import topology

    F = np.asarray(m.F)
    n = int(m.n_vertices)
    _, label = topology.connected_components(F, n)
    loops = topology.boundary_loops(F)
    chi = int(m.n_vertices) - int(m.n_edges) + int(m.n_faces)
    # genus summed over components: 2 - 2 g_i - b_i = chi_i, so sum g_i = (2c - chi - b) / 2
    used = np.zeros(n, dtype=bool)
    used[F.ravel()] = True
    n_comp_used = int(np.unique(np.asarray(label)[used]).size)
    genus2 = 2 * n_comp_used - chi - len(loops)
    periods = np.asarray(m.periods(), dtype=np.float64)
    info = {
        "vertices": n,
        "edges": int(m.n_edges),
        "faces": int(m.n_faces),
        "euler_characteristic": chi,
        "components": n_comp_used,
        "boundary_loops": len(loops),
        "genus": genus2 // 2 if genus2 % 2 == 0 else genus2 / 2,
        "periods": periods.tolist(),
        "scale": float(m.scale()),
        "max_integrability_residual": float(np.abs(m.integrability_residual()).max(initial=0.0)),
    }
    info["impossible_kind"] = impossibility_kind(m, order)
    info["impossible"] = info["impossible_kind"] is not None
    if order is not None:
        info["depth_arcs"] = int(order.n_arcs)
        info["depth_cycles"] = len(order.cycles(warn=False))
    return info


def format_info(info: dict, label: str) -> str:
    """The text ``meschers info`` prints for :func:`describe`'s dict (periods below 1e-9 of the
    model's size printed as 0: round-off, not depth)."""
    from .figures import format_values, round_off_scale

    periods = info["periods"]
    lines = [
        f"{label}",
        f"  vertices {info['vertices']}, edges {info['edges']}, faces {info['faces']}",
        f"  Euler characteristic {info['euler_characteristic']}, components {info['components']}, "
        f"boundary loops {info['boundary_loops']}, genus {info['genus']}",
        "  impossible: "
        + (
            {
                "zeta": "yes (periods: zeta does not integrate)",
                "order": "yes (through its depth order: zeta integrates, the order cannot be "
                "realised)",
            }.get(info.get("impossible_kind"), "yes")
            if info["impossible"]
            else "no"
        ),
        "  periods: "
        + (
            format_values(periods, 6, round_off_scale(periods, info.get("scale", 0.0)))
            if periods
            else "none (no loops)"
        ),
    ]
    if "depth_arcs" in info:
        lines.append(f"  depth order: {info['depth_arcs']} arcs, {info['depth_cycles']} cycles")
    return "\n".join(lines)
