"""Read the files of the spectrum probe (-solver_spectrum_solves) and describe the slowest Ritz
vectors: usage ritz_vectors.py PREFIX_SOLVE [...], e.g. /tmp/probe/s_456."""
import sys, numpy as np
from collections import defaultdict

def read_vecs(path):
    raw = open(path, 'rb').read(); out = []; o = 0
    while o < len(raw):
        cid, n = np.frombuffer(raw, '>i4', 2, o); o += 8
        assert cid == 1211214, cid
        out.append(np.frombuffer(raw, '>f8', n, o).copy()); o += 8 * n
    return out

def read_txt(path):
    res, ritz, head = [], [], open(path).readline()
    for l in open(path):
        w = l.split()
        if w[0] == 'residual': res.append(float(w[2]))
        if w[0] == 'ritz': ritz.append(float(w[2]))
    return head, np.array(res), np.array(ritz)

def its_per_decade(res):
    r = np.log10(res / res[0]); d = -r[-1]
    return len(res) - 1, d, (len(res) - 1) / d if d > 0 else np.nan

def describe(base, show=3, frac=0.9):
    head, res, ritz = read_txt(base + '.txt')
    vecs = read_vecs(base + '.bin'); X = vecs[0].reshape(-1, 3); R = vecs[1:]
    B = np.loadtxt(base + '_bonds.txt')
    i, j = B[:, 0].astype(int), B[:, 1].astype(int)
    n = len(X)
    its, dec, ipd = its_per_decade(res)
    print(head.strip(), '| decades %.1f, %.1f its/decade' % (dec, ipd))
    print('  smallest Ritz', ' '.join('%.2e' % t for t in ritz[:8]), '| largest %.3f' % ritz[-1])
    bulk = np.median(ritz)
    print('  below 0.1 x median (%.3f): %d of %d; below 0.02: %d' % (bulk, (ritz < 0.1 * bulk).sum(), len(ritz), (ritz < 0.02).sum()))
    deg = np.bincount(np.concatenate([i, j]), minlength=n)
    for k in range(min(show, len(R))):
        x = R[k].reshape(-1, 3); a2 = (x ** 2).sum(1)
        order = np.argsort(-a2); c = np.cumsum(a2[order]) / a2.sum()
        S = order[:np.searchsorted(c, frac) + 1]; inS = np.zeros(n, bool); inS[S] = True
        cut = (inS[i] != inS[j]).sum()  # intact bonds leaving the support
        # components of the support by intact bonds
        parent = np.arange(n)
        def find(u):
            while parent[u] != u: parent[u] = parent[parent[u]]; u = parent[u]
            return u
        for a, b in zip(i[inS[i] & inS[j]], j[inS[i] & inS[j]]):
            ra, rb = find(a), find(b)
            if ra != rb: parent[ra] = rb
        comps = defaultdict(list)
        for s in S: comps[find(s)].append(s)
        sizes = sorted((len(v) for v in comps.values()), reverse=True)
        # rigid fit over the support: x = t + w x (p - pbar)
        P = X[S] - X[S].mean(0); A = np.zeros((3 * len(S), 6)); A[0::3, 0] = A[1::3, 1] = A[2::3, 2] = 1
        A[0::3, 4], A[0::3, 5] = P[:, 2], -P[:, 1]; A[1::3, 3], A[1::3, 5] = -P[:, 2], P[:, 0]; A[2::3, 3], A[2::3, 4] = P[:, 1], -P[:, 0]
        y = x[S].ravel(); coef, *_ = np.linalg.lstsq(A, y, rcond=None)
        rigid = np.linalg.norm(A @ coef - y) / np.linalg.norm(y)
        print('  vec %d theta %.2e: %d nodes hold %.0f%% (of %d), %d pieces (largest %s), %d intact bonds leave it, non-rigid part %.2f, median degree %d' % (
            k, ritz[k], len(S), 100 * frac, n, len(comps), sizes[:4], cut, rigid, np.median(deg[S])))
    return X, R, ritz, res

if __name__ == '__main__':
    for b in sys.argv[1:]: describe(b)
