"""Studies over many simulations: convergence, parameter sweeps."""
