#!/usr/bin/env python3
"""Writes street-type2.ies: a synthetic LED road luminaire (IES LM-63-2002).

Not a manufacturer's file: the intensities come from the formula below,
chosen to look like a "type II" road distribution (wide along the road,
thrown a little towards the street side, little behind, nothing above the
horizon). Standard library only, so the numbers can be reproduced with

    python3 scenes/lamps/make_street_ies.py > scenes/lamps/street-type2.ies

Convention (type C photometry, written in the luminaire's own frame;
scotopia's `<emitter type="ies">` puts γ = 0 on its +z and C = 0° on its
+x, docs/lighting.md):

    γ = 0°        straight down (nadir), γ = 90° the horizon;
    C = 0°        across the road, towards the street side (over the road);
    C = 90°, 270° along the road, both ways (the file is symmetric about
                  the C0–C180 plane, so it holds C = 0°…180° only);
    C = 180°      behind the luminaire, towards the houses (house side).

The distribution, in candela, is K·(base + lobes)·cut-off with

    base   = 0.6 · cos γ · (1 + 0.8 sin γ cos C)  a soft downward component,
                                                 leaning over the road (sin γ
                                                 cos C is the direction's
                                                 component across the road,
                                                 so all planes agree at the
                                                 nadir, as they must);
    lobes  = exp(−½((γ − 67°)/14°)²) · (g(C − 75°) + g(C − 285°)),
             g(ΔC) = exp(−½(ΔC/30°)²)            the two beams along the road,
                                                 peaking at γ 67°, turned 15°
                                                 towards the street side;
    cut-off = 1 below γ 80°, then cos² down to 0 at γ 90° (full cut-off);

and K such that the luminaire emits FLUX_LM. The result (printed on
stderr): about 1900 cd at the nadir and 4100 cd in the beams, i.e.
190 and 410 cd/klm, in the range of real LED street lights.
"""

import math
import sys

FLUX_LM = 10000.0  # luminous flux of the luminaire (absolute photometry)
WATTS = 75.0  # input power: 133 lm/W, a typical LED road luminaire
GAMMA = [2.5 * i for i in range(37)]  # 0°…90° by 2.5°
C_PLANES = [5.0 * i for i in range(37)]  # 0°…180° by 5°


def relative_intensity(gamma_deg, c_deg):
    """The shape of I(γ, C), before scaling to FLUX_LM."""
    g = math.radians(gamma_deg)
    c = math.radians(c_deg)
    base = 0.6 * math.cos(g) * (1.0 + 0.8 * math.sin(g) * math.cos(c))

    def beam(centre_deg):
        d = (c_deg - centre_deg + 180.0) % 360.0 - 180.0
        return math.exp(-0.5 * (d / 30.0) ** 2)

    lobes = math.exp(-0.5 * ((gamma_deg - 67.0) / 14.0) ** 2) * (beam(75.0) + beam(285.0))
    if gamma_deg <= 80.0:
        cut = 1.0
    elif gamma_deg < 90.0:
        cut = math.cos(0.5 * math.pi * (gamma_deg - 80.0) / 10.0) ** 2
    else:
        cut = 0.0
    return (base + lobes) * cut


def flux(shape, n_gamma=900, n_c=720):
    """∫∫ I sin γ dγ dC over the lower hemisphere (midpoint rule)."""
    dg = 0.5 * math.pi / n_gamma
    dc = 2.0 * math.pi / n_c
    total = 0.0
    for i in range(n_gamma):
        g = (i + 0.5) * dg
        ring = sum(shape(math.degrees(g), math.degrees((j + 0.5) * dc)) for j in range(n_c))
        total += ring * math.sin(g) * dg * dc
    return total


def main():
    k = FLUX_LM / flux(relative_intensity)
    table = [[k * relative_intensity(g, c) for g in GAMMA] for c in C_PLANES]
    # The nadir is one direction in every plane: the beams' tails (1e-5 of
    # their peak there) differ by plane, so write their mean.
    nadir = sum(column[0] for column in table) / len(table)
    for column in table:
        column[0] = nadir
    out = sys.stdout
    out.write("IESNA:LM-63-2002\n")
    out.write("[TEST] synthetic: scotopia example, computed by scenes/lamps/make_street_ies.py\n")
    out.write("[TESTLAB] none (not a measurement)\n")
    out.write("[ISSUEDATE] 2026-12-02\n")
    out.write("[MANUFAC] scotopia example\n")
    out.write("[LUMCAT] street-type2\n")
    out.write("[LUMINAIRE] synthetic LED road luminaire, type II-like, full cut-off\n")
    out.write("[LAMP] LED 4000 K, 10000 lm (absolute photometry)\n")
    out.write("[OTHER] C0 across the road (street side), C90/C270 along it, C180 behind (house side)\n")
    out.write("TILT=NONE\n")
    # lamps, lumens per lamp (−1: absolute), candela multiplier, vertical
    # and horizontal angle counts, photometric type 1 (C), units 2
    # (metres), luminous opening 0.4 × 0.4 m, flat.
    out.write(f"1 -1 1 {len(GAMMA)} {len(C_PLANES)} 1 2 0.4 0.4 0\n")
    # ballast factor, future use, input watts
    out.write(f"1 1 {WATTS:g}\n")
    write_wrapped(out, [f"{g:g}" for g in GAMMA])
    write_wrapped(out, [f"{c:g}" for c in C_PLANES])
    for column in table:
        write_wrapped(out, [f"{v:.1f}" for v in column])
    i_peak = max(max(column) for column in table)
    print(
        f"K = {k:.1f} cd; I(0°) = {table[0][0]:.0f} cd, peak {i_peak:.0f} cd; "
        f"I(γ 67.5°) at C 0/75/90/180 = "
        + "/".join(f"{table[C_PLANES.index(c)][27]:.0f}" for c in (0.0, 75.0, 90.0, 180.0))
        + " cd",
        file=sys.stderr,
    )


def write_wrapped(out, words, per_line=10):
    for i in range(0, len(words), per_line):
        out.write(" ".join(words[i : i + per_line]) + "\n")


if __name__ == "__main__":
    main()
