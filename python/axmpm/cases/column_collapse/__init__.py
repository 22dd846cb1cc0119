"""``column_collapse``: granular column collapses against the empirical laws (docs/physics.md §6).

* :mod:`.scenario`: the collapse scenario builder (:func:`collapse_scenario`);
* :mod:`.deposit`: the deposit analysis (profiles, runout, final height);
* :mod:`.laws`: the empirical laws with their sources and confidence;
* :mod:`.case`: the validation case (a = 0.56, 0.8, 5.4), registered as ``column_collapse``;
* :mod:`.demo`: ``axmpm demo`` (the a = 0.56 column alone).
"""

from . import laws
from .case import CASE, CASES
from .deposit import deposit_metrics, geometry_from_scenario, profile_difference, profiles
from .scenario import DEFAULTS, collapse_scenario

__all__ = ["CASE", "CASES", "laws", "collapse_scenario", "DEFAULTS", "deposit_metrics", "geometry_from_scenario",
           "profile_difference", "profiles"]
