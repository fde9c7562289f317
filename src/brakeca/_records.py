"""The columns of the step kernels' per-step record array ``rec[step, :]``.

Kept apart from :mod:`brakeca._kernels` so that the code that reads run files and analyses
campaigns (:mod:`brakeca.results`) need not import numba and the kernels (about 65 MB of a
process's memory; docs/performance-history.md, eleventh session). :mod:`brakeca._kernels` re-exports
them, so ``_kernels.R_COF`` and the rest are unchanged.
"""

from __future__ import annotations

R_COF = 0  # global COF of the step [-]
R_NORMAL = 1  # band normal force [N]
R_FRICTION = 2  # friction force [N]
R_CONTACT_AREA = 3  # area in contact [m^2]
R_PRIMARY_AREA = 4  # primary plateau area [m^2]
R_SECONDARY_AREA = 5  # secondary plateau area [m^2]
R_EMITTED = 6  # volume emitted in the step [m^3]
R_GENERATED = 7  # volume generated in the step [m^3]
R_LEDGER = 8  # relative volume-ledger residual [-]
R_DISC = 9  # disc surface position z [m]
R_HELD = 10  # volume held in secondary plateaus [m^3]
R_STREAM = 11  # volume in the particle stream [m^3]
R_TARGET = 12  # demanded friction force [N]
N_REC = 13
