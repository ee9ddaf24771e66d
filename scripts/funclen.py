# funclen.py - the longest C functions of common/, sphere/, disk/ and tools/ (lines from signature to closing brace).
# usage: python3 scripts/funclen.py [N]   (from the repository root; prints the N longest, default 15)
import re,sys,glob
res=[]
for f in sorted(glob.glob('common/*.c')+glob.glob('sphere/*.c')+glob.glob('disk/*.c')+glob.glob('common/*.cpp')+glob.glob('sphere/*.cpp')+glob.glob('tools/*.c')+glob.glob('api/*.c')+glob.glob('torus/*.c')):
    L=open(f).read().split('\n')
    i=0
    while i<len(L):
        l=L[i]
        if re.match(r'^[A-Za-z_].*\)\s*\{\s*$',l) and not l.startswith(('typedef','struct','enum','if','for','while')) and '=' not in l.split('(')[0]:
            name=re.findall(r'([A-Za-z_0-9]+)\s*\(',l)
            j=i+1
            while j<len(L) and L[j]!='}': j+=1
            res.append((j-i+1,f,name[0] if name else l))
            i=j
        elif re.match(r'^[A-Za-z_].*[,(]\s*$',l) and not l.startswith(('typedef','#','static const')):
            # multi-line signature
            k=i
            while k<len(L) and not L[k].rstrip().endswith('{') and not L[k].rstrip().endswith(';'): k+=1
            if k<len(L) and L[k].rstrip().endswith('{'):
                name=re.findall(r'([A-Za-z_0-9]+)\s*\(',l)
                j=k+1
                while j<len(L) and L[j]!='}': j+=1
                res.append((j-i+1,f,name[0] if name else l))
                i=j
            else: i=k
        i+=1
res.sort(reverse=True)
for r in res[:int(sys.argv[1]) if len(sys.argv)>1 else 15]: print(*r)
