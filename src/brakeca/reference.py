"""Closed-form solutions used to verify the solver (shipped, so users can check too).

References
----------
J. Wahlström, Advances in Tribology 2016, 8181260, doi:10.1155/2016/8181260.
"""

from __future__ import annotations

import math

__all__ = ["archard_wear_depth_constant_pressure", "flat_punch_pressure"]


def flat_punch_pressure(
    friction_force: float, area: float, mu_0: float, slope: float, mu_min: float
) -> float:
    """Uniform pressure under a flat, uniform plateau surface on the Winkler foundation.

    Parameters
    ----------
    friction_force : float
        Demanded friction force F [N].
    area : float
        Total plateau area A [m^2] (all cells at the same height).
    mu_0, slope, mu_min : float
        Friction law mu(p) = max(mu_min, mu_0 - c p): [-], [1/Pa], [-].

    Returns
    -------
    float
        The smallest pressure p [Pa] with ``mu(p) p A = F`` (first root as the load grows).

    Raises
    ------
    ValueError
        ``area`` not above 0, or no pressure gives ``F``: with ``mu_min = 0`` the friction
        force has the maximum ``mu_0^2 A / (4 c)`` (the simulation's ContactError, model.md
        §5).

    Notes
    -----
    On the linear branch ``mu_0 p - c p^2 = F/A`` gives
    ``p = (mu_0 - sqrt(mu_0^2 - 4 c F/A))/(2c)`` when the discriminant is non-negative and the
    root lies above the floor (its COF at least ``mu_min``, ``p <= (mu_0 - mu_min) / c``);
    otherwise the root is on the floor branch, ``p = F / (mu_min A)``. With ``slope = 0``,
    ``p = F / (mu_0 A)``.

    On a Winkler (elastic foundation) model every bar under a flat punch is compressed alike,
    so the pressure is uniform, ``p = K (h - z)``, and the friction force is ``mu(p) p A``;
    this is the case :func:`brakeca.contact.solve_disc_position` is checked against. The
    smaller root, ``2 (F/A) / (mu_0 + sqrt(mu_0^2 - 4 c F/A))`` as computed, is the first met
    as the load grows (docs/model.md section 4, "Torque control, first root").

    References
    ----------
    K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985 (the simple elastic
    foundation model); Wahlström (2016), Figure 4 (the friction law), doi:10.1155/2016/8181260.

    Examples
    --------
    >>> from brakeca.reference import flat_punch_pressure
    >>> p = flat_punch_pressure(100.0, 1e-4, 0.6, 3e-8, 0.15)  # 100 N on 1 cm², paper's law
    >>> round(p / 1e6, 6)  # [MPa]
    1.835034
    >>> round((0.6 - 3e-8 * p) * p * 1e-4, 9)  # mu(p) p A = F [N]
    100.0
    >>> round(flat_punch_pressure(100.0, 1e-4, 0.6, 0.0, 0.15), 3)  # a constant COF: F / (mu_0 A)
    1666666.667
    """
    if not area > 0.0:
        raise ValueError(f"area must be above 0 m^2, got {area!r}")
    tau = friction_force / area
    if slope == 0.0:
        return tau / mu_0
    p_floor = (mu_0 - mu_min) / slope
    disc = mu_0 * mu_0 - 4.0 * slope * tau
    if disc >= 0.0:
        p = 2.0 * tau / (mu_0 + math.sqrt(disc))
        if p <= p_floor:
            return p
    if mu_min == 0.0:
        raise ValueError(
            f"no pressure gives a friction force of {friction_force!r} N: with mu_min = 0 the "
            f"force peaks at mu_0^2 A / (4 c) = {mu_0 * mu_0 * area / (4.0 * slope):.6g} N"
        )
    return tau / mu_min


def archard_wear_depth_constant_pressure(
    specific_wear_rate: float, pressure: float, sliding_distance: float
) -> float:
    """Archard wear depth ``h = k p s`` [m] at constant pressure ``pressure`` p [Pa] over
    ``sliding_distance`` s [m], with the specific wear rate ``specific_wear_rate`` k
    [m^3/(N m)] (= m^2/N).

    Parameters
    ----------
    specific_wear_rate : float
        Specific wear rate k [m^3/(N m)] (= m^2/N).
    pressure : float
        Contact pressure p, constant over the sliding [Pa].
    sliding_distance : float
        Sliding distance s [m].

    Returns
    -------
    float
        Wear depth h [m] (not clipped at any gap, unlike the simulation's Archard step).

    Notes
    -----
    ``h = k p s``: Archard's law, wear volume ``V = k W s`` for a normal load ``W`` slid over
    ``s``, divided by the contact area (``p = W / A``, ``h = V / A``). At constant pressure it
    is exact over any distance; :func:`brakeca.wear.archard_wear_depth` applies the same law
    step by step and clips it at the cell's interference.

    References
    ----------
    J. F. Archard, "Contact and rubbing of flat surfaces", J. Appl. Phys. 24, 981-988, 1953
    (doi:10.1063/1.1721448).

    Examples
    --------
    >>> from brakeca.reference import archard_wear_depth_constant_pressure
    >>> archard_wear_depth_constant_pressure(1e-14, 2e6, 1000.0)  # 1 km at 2 MPa: 20 µm [m]
    2e-05
    """
    return specific_wear_rate * pressure * sliding_distance
