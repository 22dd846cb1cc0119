"""``footing``: bearing capacity of a rigid footing on weightless Tresca soil.

* :mod:`.scenario`: the scenario builder, the load–settlement curve of a run and its N_c;
* :mod:`.case`: the verification case (strip and circle, smooth and rough, B/h = 10, 20, 40),
  its checks and report; registered as ``footing``.
"""

from .case import CASE
from .scenario import EXACT, bearing_capacity_factor, footing_scenario, load_settlement

__all__ = ["CASE", "EXACT", "footing_scenario", "load_settlement", "bearing_capacity_factor"]
