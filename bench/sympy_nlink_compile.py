#!/usr/bin/env python3
"""SymPy reference for bench_lagc: the same job as `phynjo-lagc nlink_N.lag -o out.cpp`.

SymPy's own model of the system, sympy.physics.mechanics.models.n_link_pendulum_on_cart(N)
(Kane's method, with the cart force), its mass_matrix_full and forcing_full, common
subexpression elimination (sympy.cse) and C code for every entry (sympy.ccode). Prints the
seconds taken and the operation count (sympy.count_ops) of the CSE'd M and f.
With --jacobian it also computes forcing_full.jacobian(states) — what an implicit or stiff
solver, or a linearization, needs — and CSEs and prints it with M and f (phynjo-lagc always
emits its Jacobians: the reference for `ratio lagc_jacobian_N`).
With --count FILE it instead counts the operations of expressions written by phynjo
(one `name = expr` per line, the .lag expression syntax) with the same counter.

usage: sympy_nlink_compile.py [--jacobian] N | sympy_nlink_compile.py --count FILE
"""
import re
import sys
import time

import sympy as sp


def count_file(path):
    total = 0
    names = {}
    for line in open(path):
        line = line.strip()
        if not line or line.startswith('#'):
            continue
        lhs, _, rhs = line.partition(' = ')
        rhs = re.sub(r"([A-Za-z_][A-Za-z0-9_]*)'", r"\1_dot", rhs.replace('^', '**'))
        expr = sp.sympify(rhs, locals=names)
        total += sp.count_ops(expr)
    return total


def c_code(M, f, start, J=None):
    """cse and C code of every entry of M and f (and J), as PyDy prints it: seconds since
    `start`, the operation count of the CSE'd expressions and the characters of C."""
    from sympy.physics.mechanics import find_dynamicsymbols
    # q_i(t), u_i(t) -> plain symbols, as PyDy does before printing code
    dyn = sorted(find_dynamicsymbols(M) | find_dynamicsymbols(f), key=str)
    plain = {x: sp.Symbol('s_%d' % k) for k, x in enumerate(dyn)}
    exprs = [e.xreplace(plain) for e in list(M) + list(f) + (list(J) if J is not None else [])]
    replacements, reduced = sp.cse(exprs)
    code = [sp.ccode(e, assign_to=str(s)) for s, e in replacements] + [sp.ccode(e) for e in reduced]
    elapsed = time.perf_counter() - start
    ops = sum(sp.count_ops(e) for _, e in replacements) + sum(sp.count_ops(e) for e in reduced)
    return elapsed, ops, sum(len(c) for c in code)


def main():
    if sys.argv[1] == '--count':
        print('ops %d' % count_file(sys.argv[2]))
        return
    from sympy.physics.mechanics.models import n_link_pendulum_on_cart
    jacobian = sys.argv[1] == '--jacobian'
    n = int(sys.argv[2] if jacobian else sys.argv[1])
    start = time.perf_counter()
    kane = n_link_pendulum_on_cart(n, cart_force=True, joint_torques=False)
    M = kane.mass_matrix_full
    f = kane.forcing_full
    J = f.jacobian(list(kane.q) + list(kane.u)) if jacobian else None
    elapsed, ops, chars = c_code(M, f, start, J)
    print('seconds %.6f' % elapsed)
    print('ops %d' % ops)
    print('code_chars %d' % chars)


if __name__ == '__main__':
    main()
