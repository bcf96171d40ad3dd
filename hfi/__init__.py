"""The machinery around the executable specification (:mod:`golden`).

``golden`` holds what the system *is* (bit-true blocks, firmware models, plant, scenarios, the golden
closed loop). This package holds what *runs and reports* it: the backends behind one interface
(:mod:`hfi.backends`), their builds (:mod:`hfi.rtl_backend`, :mod:`hfi.hls_build`, :mod:`hfi.fw_c`),
experiments (:mod:`hfi.paper`, :mod:`hfi.openloop_run`), reports (:mod:`hfi.report`) and the ``hfi``
command (:mod:`hfi.cli`). Nothing in ``golden`` imports from here.
"""

import os

# One core per simulation: numpy's OpenBLAS would start a thread per core that spins after each call (15 % more CPU
# in a golden run, scripts/env.sh). Effective when hfi is imported before numpy, as by the ``hfi`` command.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
