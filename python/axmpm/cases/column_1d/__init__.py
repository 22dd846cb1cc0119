"""``column_1d``: the 1D column under self-weight against its exact solution (docs/physics.md §4).

* :mod:`.exact`: the exact static solution (neo-Hookean and small-strain, compression and tension);
* :mod:`.scenario`: the column scenario builder and the errors of a run against the exact solution;
* :mod:`.case`: the verification case (all schemes × layouts × modes × resolutions), its checks
  and report; registered as ``column_1d``.
"""

from . import exact
from .case import CASE
from .scenario import ColumnErrors, column_errors, column_geometry, column_scenario, stress_difference

__all__ = ["CASE", "exact", "column_scenario", "column_errors", "column_geometry", "stress_difference",
           "ColumnErrors"]
