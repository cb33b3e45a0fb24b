import subprocess, gzip, io, os, re, sys
# Regenerates the golden files: python3 make.py SHAPES_DIR OSD_ORACLE_WITH_PATCH OUT_DIR
# (OSD_ORACLE_WITH_PATCH: osd-oracle built with osd-oracle-all-faces.patch applied; see README.md).
OSD=sys.argv[1]  # crates/subsurf/tests/shapes/osd
EXTRA=os.path.dirname(os.path.abspath(__file__))  # the ngon_*.obj here
OUT=sys.argv[3]  # output directory
MAXF=30
shapes=["catmark_bishop","catmark_gregory_test2","catmark_gregory_test5","catmark_gregory_test8","catmark_hole_test3","catmark_nonman_edges","catmark_nonman_verts","catmark_nonquads","catmark_pole360","catmark_pole64","catmark_pole8","catmark_pyramid","catmark_pyramid_creases0","catmark_pyramid_creases1","catmark_pyramid_creases2","catmark_rook","catmark_smoothtris0","catmark_smoothtris1","catmark_val2_back2back","catmark_val2_foldover","catmark_val2_interior","catmark_val2_nonman"]
extra=["ngon_prism12","ngon_prism17","ngon_prism40","ngon_disk20"]
skip={"catmark_val2_interior":[47,48,49]}
for name in shapes+extra:
    src=os.path.join(OSD if name in shapes else EXTRA, name+'.obj')
    text=open(src).read()
    m=re.search(r'^t interpolateboundary 1/0/0 (\d)', text, re.M)
    b={'0':'none','1':'corner'}.get(m.group(1) if m else '2','edge')
    sizes=[len(l.split())-1 for l in text.splitlines() if l.startswith('f ')]
    env=dict(os.environ)
    if name in skip: env['BFR_SKIP_FACES']=' '.join(map(str,skip[name]))
    out=subprocess.run([sys.argv[2],'limit',src,'5','--all-faces','--no-fvar','--boundary',b],capture_output=True,text=True,env=env,check=True).stdout
    rows=[l for l in out.splitlines() if l[:1].isdigit()]
    keep_quads = name in extra
    faces=sorted({int(r.split()[0]) for r in rows if keep_quads or sizes[int(r.split()[0])]!=4})
    evaluated=len(faces)
    if len(faces)>MAXF:
        faces=[faces[(k*len(faces))//MAXF] for k in range(MAXF)]
    fs=set(faces)
    kept=[r for r in rows if int(r.split()[0]) in fs]
    what = "faces" if keep_quads else "non-quad faces"
    hdr="# Bfr (OpenSubdiv 3.5, Debian libosd-dev) limit samples of %s.obj, 5 x 5 per sub-face, boundary %s; see README.md\n# %s %d, kept %d\n" % (name, b, what, evaluated, len(faces))
    buf=io.BytesIO()
    with gzip.GzipFile(filename='', mode='wb', fileobj=buf, mtime=0) as g:
        g.write((hdr+"\n".join(kept)+"\n").encode())
    open(os.path.join(OUT,name+'.txt.gz'),'wb').write(buf.getvalue())
    print(name, b, evaluated, len(faces), len(kept), len(buf.getvalue()))
