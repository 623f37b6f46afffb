"""Error of sfm_r2r_solve's first answer on noisy 7-20 step sequences (every
measurement, or a random subset per step), through the Python binding: the
scenes of tests/python/test_r2r.py, Gaussian noise on distances (m) and on
bearings (per component, then normalised). Figures: bench/README.md.
Usage: PYTHONPATH=python python bench/r2r_noise.py"""
import os, sys
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "python"))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
import numpy as np, libsfm
from test_r2r import random_scene
from libsfm import SfmError
rng=np.random.default_rng(0)
for sd, sb in [(0.0,0.0),(0.001,0.0005),(0.01,0.005),(0.05,0.02)]:
    errs=[]; nsol=[]; fails={}
    for it in range(200):
        n=int(rng.integers(7,21))
        masks=[7]*n if it%2==0 else list(rng.integers(1,8,n))
        steps,C,p=random_scene(rng,masks)
        for st in steps:
            if 'd' in st: st['d']=st['d']+rng.normal()*sd
            for k in ('b1','b2'):
                if k in st:
                    b=st[k]+rng.normal(size=3)*sb; st[k]=b/np.linalg.norm(b)
        try: sols=libsfm.r2r_solve(steps)
        except SfmError as e: fails[e.name]=fails.get(e.name,0)+1; continue
        nsol.append(len(sols))
        if sols: errs.append(max(np.abs(sols[0][0]-C).max(), np.abs(sols[0][1]-p).max()))
        else: fails['zero']=fails.get('zero',0)+1
    errs=np.array(errs)
    print(sd,sb,'median err %.3g  p90 %.3g  max %.3g'%(np.median(errs),np.percentile(errs,90),errs.max()), 'mean sols %.2f'%np.mean(nsol), fails, 'frac err>0.2: %.3f'%np.mean(errs>0.2))
