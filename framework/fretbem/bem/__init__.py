"""The boundary element body: kernels, quadrature loops, assembly, the body's system and layout."""
