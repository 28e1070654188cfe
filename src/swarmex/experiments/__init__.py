"""Many runs of a mission: scenario files (:mod:`.scenario`), sweeps (:mod:`.sweep_spec`,
:mod:`.sweep`, :mod:`.sweep_worker`, :mod:`.runstore`), the local process pool every long
experiment runs on (:mod:`.pool`), progress bars (:mod:`.progress`), a record run or drawn
again (:mod:`.rerun`) and a sweep's paired comparisons (:mod:`.compare`). docs/sweeps.md."""
