#!/usr/bin/env python3
# Derives the coefficient table COEFFICIENTS of crates/subsurf/src/limit/box_spline.rs from
# Loop's rules alone (sympy): the unique quartic basis with partition of unity that satisfies
# the refinement relation of the four children of a regular triangle. Prints 12 x (12 B_i).
"""Derive the 12 quartic box-spline basis functions of a regular Loop triangle."""
import sympy as sp
from sympy import Rational as R

# lattice offsets of the 12 control points; the triangle is (4, 5, 8) = (0,0),(1,0),(0,1)
P = [(0,-1),(1,-1),(2,-1),(-1,0),(0,0),(1,0),(2,0),(-1,1),(0,1),(1,1),(-1,2),(0,2)]
idx = {p: i for i, p in enumerate(P)}
D = [(1,0),(0,1),(-1,1),(-1,0),(0,-1),(1,-1)]
def add(a,b): return (a[0]+b[0], a[1]+b[1])
# a refined point at half-lattice position q (in parent coordinates, times 2 = integer h)
def refined(h):
    # h: integer coordinates in the child lattice (parent lattice * 2)
    if h[0] % 2 == 0 and h[1] % 2 == 0:
        p = (h[0]//2, h[1]//2)
        w = {p: R(10,16)}
        for d in D: w[add(p,d)] = w.get(add(p,d),0) + R(1,16)
        return w
    # edge point: find the parent edge whose midpoint this is
    for k, d in enumerate(D):
        a = ((h[0]-d[0])//2, (h[1]-d[1])//2)
        if (2*a[0]+d[0], 2*a[1]+d[1]) == h and (h[0]-d[0]) % 2 == 0 and (h[1]-d[1]) % 2 == 0:
            b = add(a, d)
            o1, o2 = add(a, D[(k-1)%6]), add(a, D[(k+1)%6])
            w = {}
            for x, c in [(a,R(3,8)),(b,R(3,8)),(o1,R(1,8)),(o2,R(1,8))]:
                w[x] = w.get(x,0)+c
            return w
    raise Exception(h)
u, v = sp.symbols('u v')
mons = [u**i*v**j for deg in range(5) for (i,j) in [(deg-k,k) for k in range(deg+1)]]
C = sp.Matrix(12, 15, lambda i,j: sp.Symbol(f'c_{i}_{j}'))
B = C * sp.Matrix(mons)
# children: origin (child lattice = 2*parent) and axes
children = [((0,0),(1,0),(0,1)), ((1,0),(1,0),(0,1)), ((0,1),(1,0),(0,1)), ((1,1),(-1,0),(0,-1))]
eqs = []
for (o, a1, a2) in children:
    # child point i at 2*... : child lattice coords h = o + o_i.x*a1 + o_i.y*a2 (units of half)
    S = sp.zeros(12, 12)
    for i, q in enumerate(P):
        h = (o[0] + q[0]*a1[0] + q[1]*a2[0], o[1] + q[0]*a1[1] + q[1]*a2[1])
        for p, w in refined(h).items():
            S[i, idx[p]] += w
    # parent params at child (s,t): (u,v) = (o + s a1 + t a2)/2
    s, t = sp.symbols('s t')
    pu = (o[0] + s*a1[0] + t*a2[0]) / sp.Integer(2)
    pv = (o[1] + s*a1[1] + t*a2[1]) / sp.Integer(2)
    Bc = B.subs({u: s, v: t}, simultaneous=True)
    Bp = B.subs({u: pu, v: pv}, simultaneous=True)
    lhs = S.T * Bc - Bp
    for e in lhs:
        poly = sp.Poly(sp.expand(e), s, t)
        eqs.extend(poly.coeffs())
pu_ = sp.Poly(sp.expand(sum(B) - 1), u, v)
eqs.extend(pu_.coeffs())
sol = sp.solve(eqs, list(C), dict=True)
assert len(sol) == 1
Cs = C.subs(sol[0])
assert all(x.is_number for x in Cs)
print("monomials:", mons)
for i in range(12):
    print(i, [int(x*12) for x in Cs.row(i)])
