"""Studies over many runs: parameter sweeps (:mod:`.sweep`), mesh convergence
(:mod:`.convergence`), calibration (:mod:`.calibration`), and the helpers their reports share
(:mod:`.report`: number formatting; :mod:`.plotting`: figures; :mod:`.parallel`: cores and
process pools)."""
