"""`python3 benches/pbrt_layered.py` (numpy): directional albedo of pbrt-v4's CoatedDiffuse (LayeredBxDF: a smooth dielectric over a
Lambertian base, a non-scattering layer of `thickness` that attenuates every crossing by
exp(-thickness/|cos|), the walk cut at maxDepth interface events, roulette unbiased) by
simulating its random walk, against raytree's nonlinear closed form. Independent of raytree."""
import numpy as np, sys

def fresnel(cos_i, eta):
    # unpolarised dielectric Fresnel, light arriving from the side with index 1 onto eta
    # (eta = n_t / n_i); cos_i > 0.
    sin2_t = (1 - cos_i**2) / eta**2
    tir = sin2_t >= 1
    cos_t = np.sqrt(np.clip(1 - sin2_t, 0, 1))
    rs = (cos_i - eta*cos_t) / (cos_i + eta*cos_t)
    rp = (eta*cos_i - cos_t) / (eta*cos_i + cos_t)
    r = 0.5*(rs*rs + rp*rp)
    return np.where(tir, 1.0, r), cos_t

def albedo(theta_deg, eta, rho, thickness, max_depth, n, rng):
    mu_o = np.cos(np.radians(theta_deg))
    F, cos_t = fresnel(np.full(n, mu_o), eta)
    out = F.copy()                      # reflected at the top, exact expectation
    w = 1 - F                           # weight transmitted into the layer
    mu = cos_t                          # |cos| of the direction in the layer, going down
    alive = np.ones(n, bool)
    depth = 0
    while depth < max_depth and alive.any():
        # down through the layer, then the diffuse base (depth += 1)
        w = w * np.exp(-thickness / mu)
        w = w * rho                     # Lambert: reflect rho, cosine distributed
        mu = np.sqrt(rng.random(n))     # cosine-weighted: cos = sqrt(u)
        depth += 1
        if depth >= max_depth:
            break
        # up through the layer, then the top from inside (depth += 1)
        w = w * np.exp(-thickness / mu)
        Fi, cos_out = fresnel(mu, 1/eta)   # from inside: relative index 1/eta
        out += w * (1 - Fi)             # escapes (expectation over the reflect/transmit choice)
        w = w * Fi                      # reflected back down, same |cos|
        depth += 1
    return out.mean(), out.std() / np.sqrt(n)

def closed_form(theta_deg, eta, rho):
    mu_o = np.cos(np.radians(theta_deg))
    F, _ = fresnel(np.array([mu_o]), eta)
    # F_dr,int: hemispherical (cosine-weighted) average of the inner Fresnel
    m = 200000
    u = (np.arange(m) + 0.5) / m
    mu = np.sqrt(u)                     # cosine-weighted directions
    Fi, _ = fresnel(mu, 1/eta)
    fdr = Fi.mean()
    return float(F[0] + (1 - F[0]) * rho * (1 - fdr) / (1 - rho * fdr)), fdr

if __name__ == "__main__":
    rng = np.random.default_rng(1)
    eta = 1.5
    n = 400000
    print("| base rho | theta | raytree (closed form) | walk, thickness 0, no cut | pbrt default (thickness 0.01, maxdepth 10) | pbrt / raytree |")
    print("|---|---|---|---|---|---|")
    for rho in [0.5, 0.8, 1.0]:
        for th in [0, 45, 75]:
            cf, fdr = closed_form(th, eta, rho)
            a0, e0 = albedo(th, eta, rho, 0.0, 400, n, rng)
            a1, e1 = albedo(th, eta, rho, 0.01, 10, n, rng)
            print(f"| {rho} | {th} | {cf:.4f} | {a0:.4f} +- {e0:.4f} | {a1:.4f} +- {e1:.4f} | {a1/cf:.4f} |")
    print(f"F_dr,int at eta {eta}: {fdr:.5f}")
    print("at normal incidence, each of pbrt's defaults alone, as a ratio to raytree:")
    for rho in [0.5, 0.8, 1.0]:
        cf, _ = closed_form(0, eta, rho)
        a, _ = albedo(0, eta, rho, 0.01, 400, n, rng)
        b, _ = albedo(0, eta, rho, 0.0, 10, n, rng)
        print(f"rho {rho}: thickness 0.01 alone {a / cf:.4f}, maxdepth 10 alone {b / cf:.4f}")
