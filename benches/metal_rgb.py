#!/usr/bin/env python3
"""RGB eta and k of the named conductors in src/bsdf/metals.rs, from pbrt-v4's tabulated spectra.

Usage: benches/metal_rgb.py PATH/TO/pbrt-v4/src/pbrt/util/spectrum.cpp

Reads (never copies) pbrt-v4's tables: the CIE 1931 2-degree colour matching functions CIE_X/Y/Z
(1 nm, 360..830 nm), the CIE D65 illuminant CIE_Illum_D6500 and the metal-*-eta / metal-*-k
spectra (piecewise linear, interleaved lambda/value). Each eta or k spectrum s is projected to
linear sRGB as a reflectance lit by D65 would be:

    XYZ = sum_l s(l) D65(l) cmf(l) / sum_l D65(l) ybar(l),   rgb = M_XYZ->sRGB(D65) XYZ

so a constant spectrum maps to the same constant in every channel (D65 is sRGB's white).
The spectra are linearly interpolated and held constant beyond their ends, as pbrt-v4's
PiecewiseLinearSpectrum is evaluated over 360..830 nm.
"""
import re
import sys


def table(src, name):
    m = re.search(r"const Float " + re.escape(name) + r"\[[^\]]*\] = \{(.*?)\};", src, re.S)
    return [float(x) for x in re.findall(r"[-+]?\d*\.\d+(?:[eE][-+]?\d+)?|[-+]?\d+", m.group(1))]


def piecewise(values):
    xs, ys = values[0::2], values[1::2]

    def at(l):
        if l <= xs[0]:
            return ys[0]
        if l >= xs[-1]:
            return ys[-1]
        for i in range(len(xs) - 1):
            if xs[i] <= l <= xs[i + 1]:
                t = (l - xs[i]) / (xs[i + 1] - xs[i])
                return ys[i] * (1 - t) + ys[i + 1] * t
        raise ValueError(l)

    return at


def main(path):
    src = open(path).read()
    cie = [table(src, n) for n in ("CIE_X", "CIE_Y", "CIE_Z")]
    lambdas = range(360, 831)
    d65 = piecewise(table(src, "CIE_Illum_D6500"))
    norm = sum(d65(l) * cie[1][i] for i, l in enumerate(lambdas))
    # XYZ -> linear sRGB (IEC 61966-2-1, D65).
    m = [(3.2404542, -1.5371385, -0.4985314),
         (-0.9692660, 1.8760108, 0.0415560),
         (0.0556434, -0.2040259, 1.0572252)]

    def rgb(s):
        xyz = [sum(s(l) * d65(l) * c[i] for i, l in enumerate(lambdas)) / norm for c in cie]
        return [sum(r[j] * xyz[j] for j in range(3)) for r in m]

    print("constant 1 ->", ["%.6f" % v for v in rgb(lambda l: 1.0)])
    for metal in ("Cu", "Au", "Ag", "Al"):
        eta = rgb(piecewise(table(src, metal + "_eta")))
        k = rgb(piecewise(table(src, metal + "_k")))
        print("%s eta [%s] k [%s]" % (metal, ", ".join("%.6f" % v for v in eta),
                                     ", ".join("%.6f" % v for v in k)))


if __name__ == "__main__":
    main(sys.argv[1])
