"""The tether's energies as the plant reports them, for every fidelity (compiled: the FEM's
report kernel calls it too).
"""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def tether_energies(nodes, velocities, lumps, tensions, arc, g, ea):
    """Kinetic, potential and strain energy (J) of a tether of lumped nodes: 1/2 sum m_i |v_i|^2,
    g sum m_i z_i and sum_k T_k^2 (s_k+1 - s_k) / (2 EA), with T_k the tension between nodes k
    and k + 1 and s the nodes' unstretched arc length: Eq. 7.7's 1/2 EA eps^2 with eps = T / EA
    constant over each interval.
    """
    kinetic = potential = strain = 0.0
    for i in range(nodes.shape[0]):
        kinetic += lumps[i] * (velocities[i, 0] ** 2 + velocities[i, 1] ** 2 + velocities[i, 2] ** 2)
        potential += lumps[i] * nodes[i, 2]
    for k in range(nodes.shape[0] - 1):
        strain += tensions[k] ** 2 * (arc[k + 1] - arc[k])
    return 0.5 * kinetic, g * potential, strain / (2.0 * ea)
