"""Test-session settings shared by every test folder."""

import os

# The contact Newton solves many small dense systems; on a loaded 2-core machine BLAS
# threads fight over the cores and slow each solve 10-40x. One thread is the fast choice
# for these sizes (set before numpy is first imported).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
