"""Reductions from one kind of problem to another, as apply/recover pairs (the pattern of
cvxpy's reductions): building a reduction object *applies* it (the reduced problem's data
become its attributes), and its methods *recover* the original problem's answer (a point,
a direction, a basis) from the reduced one's.  Each is testable alone
(``tests/test_reductions.py``).

* ``qp_mlcp.QPToMLCP``   -- a convex QP to the monotone MLCP of its KKT conditions;
* ``mlcp_lcp.MLCPToLCP`` -- an MLCP to an LCP by exchange pivots on its free variables.

New kinds plug in here: a box LCP or a bimatrix game that is solved through an LCP gets a
module with its reduction (a game: Lemke-Howson's LCP of the two best-response
polytopes), registered with its kind in ``lemke/_kinds.py``.
"""
