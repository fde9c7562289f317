"""brakeca: cellular-automaton simulation of brake pad friction, wear and wear emissions.

Implements the simplified cellular-automaton model of

    J. Wahlström, "A Factorial Design to Numerically Study the Effects of Brake Pad
    Properties on Friction and Wear Emissions", Advances in Tribology, 2016,
    Article ID 8181260. doi:10.1155/2016/8181260
"""

__version__ = "0.1.0"

from brakeca._cachedir import configure as _configure_numba_cache

_configure_numba_cache()
