"""Typed records of obtaining a mescher: junctions, the conversion report, the seen model,
and the gluing of a visible map's shared screen edges."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Junction:
    """A glued false edge (a connected chain of screen edges) or a bridged hidden gap.

    Attributes
    ----------
    kind : str
        ``"false edge"`` (visible junction), ``"bar joint"`` (a bar's end hidden exactly behind
        another's, its face continued behind the near bar and glued across the near face's
        edge: :mod:`~meschers_igl.obtain.bar_joints`), ``"hidden gap"`` (amodal bridge across a
        depth offset), ``"occluded continuation"`` (amodal bridge without offset) or
        ``"crossing"`` (a bar broken in line, completed behind the bar seen through its gap: no
        offset, an order a viewer cannot realise).
    position : (2,) float
        Screen position (middle of the chain).
    depth_gap : float
        Depth of the far side minus the near side is ``-depth_gap``: the jump a loop through
        the junction gains, i.e. (up to sign and multiplicity) the period it creates.
    n_edges : int
        Screen edges in the chain.
    """

    kind: str
    position: np.ndarray
    depth_gap: float
    n_edges: int


@dataclass
class ConversionReport:
    """What :func:`see_model` found and did.

    Attributes
    ----------
    junctions : list of Junction
    n_arcs : int
        Depth-order arcs added (true occlusions and bridges behind their occluders).
    repairs : list of str
        Clean-up steps that changed the input (welds, flips, dropped faces).
    warnings : list of str
    snapped : (#F,) float or None
        ``perceive="manhattan"`` only: angle (radians) each mescher face's normal was snapped.
    view, up : (3,) float
        The view used (``view="auto"`` reports the one it found).
    source_face : (#F,) int64
        Input face (after clean-up) each mescher face comes from (-1 for bridge faces: the
        visible path's strips, the closed path's tubes).
    arcs : (k, 2) int64
        The depth-order arcs ``i -> j`` (face ``i`` behind face ``j``).
    cleanup : object or None
        A loader's clean-up report (``meshlab_filters`` puts its ``CleanupReport`` here).
    route : {"cut", "closed", "visible"}
        How the mescher was obtained: the cut model glued at its seam, the whole model opened
        at its junctions and glued crosswise, or the visible surface.
    reason : str
        Why that route was taken.
    """

    junctions: list = field(default_factory=list)
    n_arcs: int = 0
    repairs: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    snapped: np.ndarray | None = None
    arcs: np.ndarray | None = None
    view: np.ndarray | None = None
    up: np.ndarray | None = None
    source_face: np.ndarray | None = None
    cleanup: Any = None
    route: str = "visible"
    reason: str = ""

    def __str__(self) -> str:
        lines = [f"route: {self.route} ({self.reason})" if self.reason else f"route: {self.route}"]
        lines.append(f"view {np.round(self.view, 6).tolist()}, up {np.round(self.up, 6).tolist()}")
        for j in self.junctions:
            lines.append(
                f"{j.kind} at screen ({j.position[0]:.4g}, {j.position[1]:.4g}): depth gap "
                f"{j.depth_gap:.6g} over {j.n_edges} edge(s)"
            )
        lines.append(f"{self.n_arcs} depth-order arc(s)")
        if self.snapped is not None:
            lines.append(
                f"normals snapped to the perceived frame: max {np.degrees(self.snapped.max()):.3g}"
                f" deg, mean {np.degrees(self.snapped.mean()):.3g} deg"
            )
        if self.cleanup is not None:
            lines.append(f"clean-up: {self.cleanup}")
        lines += [f"repair: {r}" for r in self.repairs]
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)


@dataclass
class VisibleModel:
    """Arrays of the visible surface (build the mescher with ``Mescher.from_corner_depths``).

    Attributes
    ----------
    F : (#F, 3) int64
        Oriented triangles (counter-clockwise on screen).
    xy : (#V, 2) float64
    Z : (#F, 3) float64
        Corner depths of each face, from its source face's plane (corner-wise, so faces on the
        two sides of a false edge disagree by the depth gap; their zeta agrees).
    arcs : (k, 2) int64
        Depth-order arcs ``i -> j``: face ``i`` behind face ``j``.
    report : ConversionReport
    """

    F: np.ndarray
    xy: np.ndarray
    Z: np.ndarray
    arcs: np.ndarray
    report: ConversionReport


@dataclass(frozen=True)
class Glue:
    """How the shared screen edges of a visible map are joined.

    Attributes
    ----------
    h1, h2 : (k,) int64
        The two half-edges (``3 f + c``: edge ``c`` of face ``f`` runs corner ``c+1 -> c+2``)
        of each shared screen edge; ``h2`` runs the other way.
    glued : (k,) bool
        Joined (continuous or a false edge); else cut (a true occlusion).
    continuous : (k,) bool
        The model's surface is continuous there (same depth on both sides).
    """

    h1: np.ndarray
    h2: np.ndarray
    glued: np.ndarray
    continuous: np.ndarray

    def with_glued(self, glued: np.ndarray) -> Glue:
        return Glue(self.h1, self.h2, glued, self.continuous)


@dataclass(frozen=True)
class EdgeSides:
    """The two sides of each shared screen edge, each seen on its own model edge.

    Attributes
    ----------
    h1, h2 : (k,) int64
        The two half-edges (as in :class:`Glue`).
    far1 : (k,) bool
        ``h1``'s face is the farther one.
    edge1, edge2 : (k,) int64
        Per side, the model edge ``c`` (corners ``c -> c+1`` of its model face) the screen edge
        lies on (0 where it lies on none).
    across1, across2 : (k,) int64
        Per side, the model face across that model edge (-1: a boundary edge).
    ends1, ends2 : (k,) bool
        Per side, whether its surface ends at that edge as seen (a silhouette or a boundary).
    """

    h1: np.ndarray
    h2: np.ndarray
    far1: np.ndarray
    edge1: np.ndarray
    edge2: np.ndarray
    across1: np.ndarray
    across2: np.ndarray
    ends1: np.ndarray
    ends2: np.ndarray

    def far_near(self, name: str, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Field ``name`` (``"h"``, ``"edge"``, ``"across"`` or ``"ends"``) at ``rows`` for the
        farther side, then for the nearer one."""
        a, b = getattr(self, f"{name}1")[rows], getattr(self, f"{name}2")[rows]
        far = self.far1[rows]
        return np.where(far, a, b), np.where(far, b, a)


@dataclass(frozen=True)
class FalseEdges:
    """The false edges of a visible map and the occluded edges a bridge may continue.

    Attributes
    ----------
    E : (k, 2) int64
        Screen vertices of each false edge (tail, head as in its first face).
    gap : (k,) float64
        Depth of the second side minus the first, averaged over the edge's ends.
    occluded : (m,) int64
        Half-edges on the far side of true occlusions where the far surface continues.
    """

    E: np.ndarray
    gap: np.ndarray
    occluded: np.ndarray
