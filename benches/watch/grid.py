"""A 708 x 708 wavy grid (999,698 triangles) as a binary PLY, for `prism watch`'s restart latency (latency.sh).

    python3 grid.py AMPLITUDE OUT.ply   (written to OUT.ply.tmp and renamed over OUT.ply, as editors save)
"""
import os
import sys

import numpy as np

amp, out = float(sys.argv[1]), sys.argv[2]
n = 708
xs=np.linspace(-1,1,n); X,Y=np.meshgrid(xs,xs)
Z=amp*np.sin(8*X)*np.cos(8*Y)
v=np.stack([X.ravel(),Z.ravel(),Y.ravel()],1).astype('<f4')
idx=np.arange(n*n).reshape(n,n)
a=idx[:-1,:-1].ravel(); b=idx[:-1,1:].ravel(); c=idx[1:,:-1].ravel(); d=idx[1:,1:].ravel()
f=np.concatenate([np.stack([a,c,b],1),np.stack([b,c,d],1)])
hdr=f"ply\nformat binary_little_endian 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\nelement face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n".encode()
rec=np.zeros(len(f),dtype=[('n','u1'),('i','<i4',3)]); rec['n']=3; rec['i']=f
data=hdr+v.tobytes()+rec.tobytes()
open(out + '.tmp', 'wb').write(data)
os.replace(out + '.tmp', out)
