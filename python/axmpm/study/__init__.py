"""Studies over many runs: parameter sweeps (:mod:`.sweep`), mesh convergence
(:mod:`.convergence`) and calibration (:mod:`.calibration`). Their reports share
:mod:`axmpm.report` (number formatting) and :mod:`axmpm.plotting` (figures) with the cases, and
:mod:`axmpm.run.parallel` (cores, process pools, Dask clients) with the case driver."""
