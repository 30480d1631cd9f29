import numpy as np, struct, sys, os
def load(path):
    ext = os.path.splitext(path)[1].lower()
    if ext == '.obj':
        V=[];F=[]
        for line in open(path, errors='replace'):
            if line.startswith('v '):
                V.append([float(x) for x in line.split()[1:4]])
            elif line.startswith('f '):
                idx=[int(w.split('/')[0]) for w in line.split()[1:]]
                idx=[i-1 if i>0 else len(V)+i for i in idx]
                for k in range(1,len(idx)-1): F.append([idx[0],idx[k],idx[k+1]])
        V=np.array(V);F=np.array(F)
        return V[F]
    if ext == '.stl':
        data=open(path,'rb').read()
        if data[:5]==b'solid' and b'facet' in data[:400]:
            pts=[]
            for line in data.decode(errors='replace').splitlines():
                s=line.split()
                if s and s[0]=='vertex': pts.append([float(x) for x in s[1:4]])
            return np.array(pts).reshape(-1,3,3)
        n=struct.unpack('<I',data[80:84])[0]
        a=np.frombuffer(data[84:84+50*n],dtype=np.dtype([('n','<f4',3),('v','<f4',(3,3)),('a','<u2')]))
        return a['v'].astype(float)
    if ext == '.ply':   # the binary PLY written by save_ply below (float x y z; uchar-int faces of 3)
        data=open(path,'rb').read(); end=data.index(b'end_header\n')+11
        hdr=data[:end].decode().split('\n')
        nv=int([l for l in hdr if l.startswith('element vertex')][0].split()[2])
        nf=int([l for l in hdr if l.startswith('element face')][0].split()[2])
        V=np.frombuffer(data[end:end+12*nv],dtype='<f4').reshape(-1,3).astype(float)
        F=np.frombuffer(data[end+12*nv:end+12*nv+13*nf],dtype=np.dtype([('n','u1'),('i','<i4',3)]))['i']
        return V[F]
    raise ValueError(ext)
def save_stl(path, T, name=b'ausbau bench-real'):
    T=np.asarray(T,dtype=np.float32)
    n=np.cross(T[:,1]-T[:,0],T[:,2]-T[:,0]); l=np.linalg.norm(n,axis=1,keepdims=True); l[l==0]=1; n=(n/l).astype(np.float32)
    rec=np.zeros(len(T),dtype=np.dtype([('n','<f4',3),('v','<f4',(3,3)),('a','<u2')]))
    rec['n']=n; rec['v']=T
    with open(path,'wb') as f:
        f.write(name.ljust(80,b' ')[:80]); f.write(struct.pack('<I',len(T))); f.write(rec.tobytes())
def bbox(T):
    P=T.reshape(-1,3); return P.min(0),P.max(0)
def pt_tri_dist(P, T):
    """min distance from each point in P to the triangle set T (Ericson), brute force chunks"""
    A=T[:,0];B=T[:,1];C=T[:,2]
    out=np.full(len(P),np.inf)
    lo=T.min(1);hi=T.max(1)
    for s in range(0,len(P),256):
        p=P[s:s+256][:,None,:]
        ab=B-A;ac=C-A;ap=p-A
        d1=(ab*ap).sum(-1);d2=(ac*ap).sum(-1)
        bp=p-B;d3=(ab*bp).sum(-1);d4=(ac*bp).sum(-1)
        cp=p-C;d5=(ab*cp).sum(-1);d6=(ac*cp).sum(-1)
        va=d3*d6-d5*d4;vb=d5*d2-d1*d6;vc=d1*d4-d3*d2
        den=va+vb+vc; den=np.where(den==0,1e-300,den)
        v=vb/den;w=vc/den
        q=A+ab*v[...,None]+ac*w[...,None]
        # regions
        def seg(a,b):
            ab_=b-a; t=np.clip(((p-a)*ab_).sum(-1)/np.maximum((ab_*ab_).sum(-1),1e-300),0,1)
            return a+ab_*t[...,None]
        qab=seg(A,B);qac=seg(A,C);qbc=seg(B,C)
        inside=(va>=0)&(vb>=0)&(vc>=0)
        dq=np.where(inside,np.linalg.norm(p-q,axis=-1),np.inf)
        dm=np.minimum(np.minimum(np.linalg.norm(p-qab,axis=-1),np.linalg.norm(p-qac,axis=-1)),np.linalg.norm(p-qbc,axis=-1))
        out[s:s+256]=np.minimum(dq,dm).min(1)
    return out
def winding(P, T):
    """generalized winding number of points P wrt closed mesh T (~1 inside, ~0 outside)"""
    out=np.zeros(len(P))
    for s in range(0,len(P),128):
        p=P[s:s+128][:,None,None,:]
        a=T[None]-p  # (n,t,3,3)
        la=np.linalg.norm(a,axis=-1)
        A,B,C=a[:,:,0],a[:,:,1],a[:,:,2]
        num=(A*np.cross(B,C)).sum(-1)
        den=la[...,0]*la[...,1]*la[...,2]+(A*B).sum(-1)*la[...,2]+(A*C).sum(-1)*la[...,1]+(B*C).sum(-1)*la[...,0]
        out[s:s+128]=np.arctan2(num,den).sum(1)/(2*np.pi)
    return out
def surface_points(T, per_edge=2):
    pts=[T.reshape(-1,3)]
    for k in range(1,per_edge+1):
        f=k/(per_edge+1)
        for i,j in ((0,1),(1,2),(2,0)): pts.append(T[:,i]*(1-f)+T[:,j]*f)
    pts.append(T.mean(1))
    return np.unique(np.round(np.concatenate(pts),12),axis=0)
def near(P, T, margin):
    lo,hi=bbox(T); m=np.all((P>lo-margin)&(P<hi+margin),axis=1); return P[m]
def tris_near(T, lo, hi, margin):
    a=T.min(1);b=T.max(1); m=np.all((b>lo-margin)&(a<hi+margin),axis=1); return T[m]
def gap(D, S, margin):
    """min surface distance (approx by sampled points of each vs triangles of the other) and
    penetration: fraction/count of D sample points inside S and S points inside D"""
    lo,hi=bbox(D); Sn=tris_near(S,lo,hi,margin)
    if len(Sn)==0: return dict(min_dist=None)
    PD=near(surface_points(D),Sn,margin); lo2,hi2=bbox(Sn); Dn=tris_near(D,lo2,hi2,margin)
    PS=near(surface_points(Sn),Dn,margin)
    dd=pt_tri_dist(PD,Sn) if len(PD) else np.array([np.inf])
    ds=pt_tri_dist(PS,Dn) if len(PS) else np.array([np.inf])
    return dict(min_dist=float(min(dd.min(),ds.min())), nD=len(PD), nS=len(PS))
def inside_count(P, T, thresh=0.5):
    w=winding(P,T); return int((w>thresh).sum()), w
def load_indexed_obj(path):
    V=[];F=[]
    for line in open(path, errors='replace'):
        if line.startswith('v '): V.append([float(x) for x in line.split()[1:4]])
        elif line.startswith('f '):
            idx=[int(w.split('/')[0]) for w in line.split()[1:]]
            idx=[i-1 if i>0 else len(V)+i for i in idx]
            for k in range(1,len(idx)-1): F.append([idx[0],idx[k],idx[k+1]])
    return np.array(V),np.array(F)
def save_ply(path, V, F, comment='ausbau bench-real'):
    V=np.asarray(V,dtype='<f4'); F=np.asarray(F,dtype='<i4')
    hdr=('ply\nformat binary_little_endian 1.0\ncomment %s\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
         'element face %d\nproperty list uchar int vertex_indices\nend_header\n')%(comment,len(V),len(F))
    rec=np.zeros(len(F),dtype=np.dtype([('n','u1'),('i','<i4',3)])); rec['n']=3; rec['i']=F
    with open(path,'wb') as f: f.write(hdr.encode()); f.write(V.tobytes()); f.write(rec.tobytes())
def quat_rpy(r,p,y):
    cr,sr=np.cos(r/2),np.sin(r/2);cp,sp=np.cos(p/2),np.sin(p/2);cy,sy=np.cos(y/2),np.sin(y/2)
    return np.array([cr*cp*cy+sr*sp*sy, sr*cp*cy-cr*sp*sy, cr*sp*cy+sr*cp*sy, cr*cp*sy-sr*sp*cy])
def qmul(a,b):
    w1,x1,y1,z1=a;w2,x2,y2,z2=b
    return np.array([w1*w2-x1*x2-y1*y2-z1*z2,w1*x2+x1*w2+y1*z2-z1*y2,w1*y2-x1*z2+y1*w2+z1*x2,w1*z2+x1*y2-y1*x2+z1*w2])
def qmat(q):
    w,x,y,z=q
    return np.array([[1-2*(y*y+z*z),2*(x*y-w*z),2*(x*z+w*y)],[2*(x*y+w*z),1-2*(x*x+z*z),2*(y*z-w*x)],[2*(x*z-w*y),2*(y*z+w*x),1-2*(x*x+y*y)]])
def place(T,q,t): return T@qmat(q).T+np.asarray(t)
