#!/usr/bin/env python3
"""Prints the constants of libsfm/core/dmath.c from exact arithmetic (Python's
decimal at 500 digits and fractions): pi by Machin's formula, ln 2 as
2 atanh(1/3), atan(i/8) by its series, their binary64 head/tail splits, the
words of 2/pi and the Taylor coefficients. Not needed at build time; run it
to check or extend the tables."""
from decimal import Decimal as D, getcontext
from fractions import Fraction as F
import struct, math
getcontext().prec = 500
def atan_series(x):  # x Decimal small
    s = D(0); t = x; n = 1; x2 = x*x; sign = 1
    while True:
        term = t / n
        if abs(term) < D(10)**-450: break
        s += sign*term; t *= x2; n += 2; sign = -sign
    return s
# pi by Machin
PI = 16*atan_series(D(1)/5) - 4*atan_series(D(1)/239)
def ln2():
    # ln2 = 2 atanh(1/3)
    s = D(0); x = D(1)/3; t = x; n = 1
    while t > D(10)**-450:
        s += t/n; t *= x*x; n += 2
    return 2*s
LN2 = ln2()
def nearest(d):
    fr = F(d)
    return float(fr)  # Fraction->float correctly rounded
def hx(v): return float.hex(v)
def trunc_bits(d, bits):
    # d positive Decimal: keep top `bits` significant bits
    fr = F(d); e = math.floor(math.log2(float(fr)))
    scale = F(2)**(bits-1-e)
    return float(F(math.floor(fr*scale))/scale)
ln2hi = trunc_bits(LN2, 40); ln2lo = nearest(LN2 - D(ln2hi))
print("LN2_HI", hx(ln2hi), "LN2_LO", hx(ln2lo))
print("INV_LN2", hx(nearest(1/LN2)))
ih = nearest(1/LN2); print("INV_LN2_HI", hx(ih), "INV_LN2_LO", hx(nearest(1/LN2 - D(ih))))
pio2 = PI/2
rem = pio2; parts=[]
for b in (33,33,33):
    p = trunc_bits(rem, b) ; parts.append(p); rem = rem - D(p)
parts.append(nearest(rem))
print("PIO2_P", [hx(p) for p in parts])
for name, v in (("PI", PI), ("PIO2", pio2), ("PIO4", PI/4)):
    h = nearest(v); print(name+"_HI", hx(h), name+"_LO", hx(nearest(v - D(h))))
print("INV_PIO2", hx(nearest(2/PI)))
for k in range(9):
    a = atan_series(D(k)/8) if k < 8 else PI/4
    h = nearest(a); print("ATAN", k, hx(h), hx(nearest(a - D(h))))
# 2/pi bits as 32-bit words
tp = 2/PI
words=[]; fr = F(tp)
for i in range(44):
    fr *= 2**32; w = math.floor(fr); words.append(w); fr -= w
print("TWO_OVER_PI", ", ".join("0x%08xu" % w for w in words))
fact = [math.factorial(i) for i in range(30)]
print("INVFACT", [hx(float(F(1, fact[i]))) for i in range(20)])
print("INV_ODD", [hx(float(F(1, 2*n+1))) for n in range(20)])
print("TWO_OVER_ODD", [hx(float(F(2, 2*n+1))) for n in range(20)])
print("SQRT2_2", hx(nearest(D(2).sqrt()/2)))
