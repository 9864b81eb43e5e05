# Regenerates the expected values in tests/unit/functions_test.cpp (run: python3 derive_expected.py).
# Independent derivation of expected func() values: Cox-de Boor recursion
# (not de Boor's algorithm used in Functions.cpp) over lpfg's knot vector.
import struct, sys
def f32(v): return struct.unpack('f', struct.pack('f', v))[0]

def load(pts):
    P=[]
    for x,y,m in pts: P += [(f32(x),f32(y))]*m
    return P

def knots(m):  # lpfg: 0,0,0,0,1,..,m-4,m-3,m-3,m-3,m-3
    return [0]*4 + list(range(1, m-3)) + [m-3]*4

def N(i,k,u,t):  # order k basis, half-open spans; right end handled by caller
    if k==1:
        return 1.0 if t[i] <= u < t[i+1] else 0.0
    s=0.0
    if t[i+k-1]-t[i]: s += (u-t[i])/(t[i+k-1]-t[i])*N(i,k-1,u,t)
    if t[i+k]-t[i+1]: s += (t[i+k]-u)/(t[i+k]-t[i+1])*N(i+1,k-1,u,t)
    return s

def point(P,d):
    m=len(P); t=knots(m); umax=m-3
    if d>=1.0: return P[-1]   # limit at the end point
    u=d*umax
    x=sum(P[i][0]*N(i,4,u,t) for i in range(m))
    y=sum(P[i][1]*N(i,4,u,t) for i in range(m))
    return x,y

def exact_y(P,x):
    lo,hi=0.0,1.0
    for _ in range(200):
        mid=(lo+hi)/2
        if point(P,mid)[0] > x: hi=mid
        else: lo=mid
    return point(P,(lo+hi)/2)[1]

def lpfg_table(P,n):
    vals=[]
    maxerr=f32(f32(0.01)/n)
    for i in range(n):
        target=f32(i/(n-1)); lo,hi=0.0,1.0
        for _ in range(100):
            c=(lo+hi)/2; X,Y=point(P,c)
            if X>target: hi=c
            else: lo=c
            if abs(X-target)<=maxerr: break
        vals.append(f32(Y))
    return vals

def lookup(vals,v):
    n=len(vals); idx=f32(v*(n-1)); i=int(idx)
    if i>=n-1: return vals[-1]
    w2=idx-i
    return (1-w2)*vals[i]+w2*vals[i+1]

leaf=load([(0,0,1),(0.15,0.05,1),(0.3,0.65,1),(0.55,0.95,2),(0.8,0.7,1),(1,0.6,1)])
tab=lpfg_table(leaf,20)
print("leaf.func (20 samples)")
for x in [0.0,0.1,0.25,0.5,10/19,0.75,0.9,1.0]:
    print(f"  x={x:.6f} table={lookup(tab,f32(x)):.7f} exact_curve={exact_y(leaf,x):.7f}")
lin=load([(0,2,1),(0.333333,3,1),(0.666667,4,1),(1,5,1)])
tl=lpfg_table(lin,100)
print("linear.func (100 samples)")
for x in [0.0,0.25,0.5,0.73,1.0]:
    print(f"  x={x} table={lookup(tl,f32(x)):.7f} exact_curve={exact_y(lin,x):.7f} 2+3x={2+3*x}")
