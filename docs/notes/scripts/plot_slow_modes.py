"""Figure of docs/notes/slow-modes.md: the smallest Ritz values of every probe, and the two
slowest Ritz vectors of one probe (node amplitude in the x-z plane)."""
import sys, glob, re, numpy as np
import matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot as plt
sys.path.insert(0, sys.argv[1]); from ritz_vectors import read_txt, read_vecs  # argv: scripts dir, probe dir, peak solve, probe base, png
d, peak_solve, show, out = sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5]
files = [f for f in glob.glob(d + '/s_*.txt') if 'bonds' not in f]
fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
for f in files:
    head, res, ritz = read_txt(f)
    s = int(re.findall(r'solve (\d+),', head)[0]); tie = 'rtol 1e-10' in head
    if len(ritz): ax[0].semilogy([s] * min(8, len(ritz)), ritz[:8], 'o' if not tie else 's', ms=3, color='C3' if tie else 'C0')
ax[0].axvline(peak_solve, color='k', lw=0.8); ax[0].set_xlabel('solve'); ax[0].set_ylabel('8 smallest Ritz values of $M^{-1}K$')
ax[0].set_title('mini sample, main job (squares: rtol 1e-10 re-solves)', fontsize=9)
X = read_vecs(show + '.bin'); C = X[0].reshape(-1, 3)
for k, a in zip((0, 1), ax[1:]):
    x = X[1 + k].reshape(-1, 3); amp = np.sqrt((x ** 2).sum(1)); o = np.argsort(amp)
    sc = a.scatter(C[o, 0], C[o, 2], c=amp[o] / amp.max(), s=4 + 30 * amp[o] / amp.max(), cmap='viridis')
    big = amp > 0.3 * amp.max()
    a.quiver(C[big, 0], C[big, 2], x[big, 0], x[big, 2], color='r', width=0.003)
    head, res, ritz = read_txt(show + '.txt')
    a.set_title('Ritz vector %d, theta = %.1e (solve %s)' % (k, ritz[k], re.findall(r'_(\d+)$', show)[0]), fontsize=9)
    a.set_xlabel('x'); a.set_ylabel('z (load)'); a.set_aspect('equal'); plt.colorbar(sc, ax=a, label='|u| / max')
plt.tight_layout(); plt.savefig(out, dpi=90)
