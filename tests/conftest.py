"""Test-session settings shared by every test folder."""

import os

# The contact Newton solves many small dense systems; on a loaded 2-core machine BLAS
# threads fight over the cores and slow each solve 10-40x. One thread is the fast choice
# for these sizes (set before numpy is first imported).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import pytest


@pytest.fixture(autouse=True)
def _fresh_assembly_budget():
    """Each test starts with no numpy assembly spent, so its own runs take one path.

    The automatic choice of assembly loops counts work across a process
    (fretbem.bem.integration); without this, two runs compared bit for bit in one test could
    straddle the switch depending on which tests ran before.
    """
    from fretbem.bem import integration

    integration.LOOP_CHOICE.reset()
    yield


@pytest.fixture
def patch_run(monkeypatch):
    """Replace fretbem.simulation.run everywhere it is bound (modules import it by name)."""
    import sys

    from fretbem import simulation

    def patch(fake):
        original = simulation.run
        for name, module in list(sys.modules.items()):
            if name.startswith("fretbem") and getattr(module, "run", None) is original:
                monkeypatch.setattr(module, "run", fake)

    return patch
