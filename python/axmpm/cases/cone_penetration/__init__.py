"""``cone_penetration``: the cone penetration test in undrained (Tresca) clay.

* :mod:`.scenario`: the scenario builder, the cone factor against depth of a run, its steady
  value and the two reference formulas;
* :mod:`.case`: the verification case (I_r = 50, 100, 300, 500; smooth and rough; R/h = 4, 8;
  a domain check), its checks and report; registered as ``cone_penetration``.
"""

from .case import CASE
from .scenario import cone_scenario, lu_et_al, penetration_curve, steady_cone_factor, teh_houlsby

__all__ = ["CASE", "cone_scenario", "penetration_curve", "steady_cone_factor", "lu_et_al", "teh_houlsby"]
