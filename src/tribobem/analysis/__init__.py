"""Analysis of results: friction loops (measured and simulated), their branches and lateral
stiffness (:mod:`.loops`)."""
