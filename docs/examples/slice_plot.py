"""f_r in the plane of incidence, for a few viewing angles, on a log scale (docs/python.md).

    PYTHONPATH=build/python /usr/bin/python3 docs/examples/slice_plot.py [MATERIAL] [OUT.png]

MATERIAL is anything zbrdf.load accepts (default merl:blue-acrylic): a spec, a file or a session.
The viewer sits at (theta_o, phi_o = 0); the light sweeps the same plane, theta_i signed: > 0 on
the mirror side (phi_i = pi), < 0 on the viewer's side (phi_i = 0, toward retro-reflection).
"""
import sys

import matplotlib

matplotlib.use("Agg")  # files only; no display needed
import matplotlib.pyplot as plt
import numpy as np

import zbrdf

material = sys.argv[1] if len(sys.argv) > 1 else "merl:blue-acrylic"
out = sys.argv[2] if len(sys.argv) > 2 else "slice.png"
brdf = zbrdf.load(material)

theta_i_deg = np.linspace(-89.5, 89.5, 717)
w_i = zbrdf.direction(np.radians(np.abs(theta_i_deg)), np.where(theta_i_deg >= 0, np.pi, 0.0))

fig, ax = plt.subplots(figsize=(7, 4.5))
for theta_o_deg, color in zip([0, 30, 60, 75], ["C0", "C1", "C2", "C3"]):
    w_o = zbrdf.direction(np.radians(theta_o_deg), 0.0)  # one view for every w_i
    f = brdf.eval(w_i, w_o)  # (N, 3): f_r in 1/sr, linear RGB, no cosine
    luminance = f @ np.array([0.2126, 0.7152, 0.0722])  # Rec. 709 weights
    ax.semilogy(theta_i_deg, np.maximum(luminance, 1e-6), color=color,
                label="theta_o = %d deg" % theta_o_deg)
    ax.axvline(theta_o_deg, color=color, linestyle=":", linewidth=0.8)  # the mirror direction
ax.set_xlabel("theta_i (deg); > 0: mirror side, < 0: viewer's side")
ax.set_ylabel("f_r luminance (1/sr)")
ax.set_title("%s: plane of incidence" % brdf.name)
ax.grid(True, which="both", alpha=0.3)
ax.legend()
fig.tight_layout()
fig.savefig(out, dpi=120)
print("wrote %s (%s)" % (out, brdf.description))
