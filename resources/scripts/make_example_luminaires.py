"""Writes resources/examples/downlight.ies and downlight.ldt: one LED downlight (1500 lm of lamps,
I = 900 cd x cos^3(gamma) out to 60 degrees, falling linearly to nothing at 75: a 20 cm recessed
fitting with a soft cut-off), in IES LM-63-2002 and EULUMDAT, for trying photometric lamps.

    python3 resources/scripts/make_example_luminaires.py
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.normpath(os.path.join(HERE, "..", "examples"))
LAMP_LM = 1500.0


def candela(gamma):
    if gamma <= 60:
        return 900.0 * math.cos(math.radians(gamma)) ** 3
    if gamma >= 75:
        return 0.0
    return 900.0 * math.cos(math.radians(60)) ** 3 * (75 - gamma) / 15.0


def main():
    gammas = list(range(0, 91, 5))
    ies = ["IESNA:LM-63-2002", "[TEST] Relume example", "[MANUFAC] Relume", "[LUMCAT] RL-DL-20",
           "[LUMINAIRE] LED downlight, 20 cm, recessed", "[LAMP] LED module 1500 lm 3000 K", "TILT=NONE",
           "1 %.0f 1 %d 1 1 2 0.2 0.2 0" % (LAMP_LM, len(gammas)), "1 1 14",
           " ".join(str(g) for g in gammas), "0", " ".join("%.1f" % candela(g) for g in gammas)]
    with open(os.path.join(OUT, "downlight.ies"), "w") as f:
        f.write("\r\n".join(ies) + "\r\n")
    ng = list(range(0, 181, 5))
    ldt = ["Relume example", "1", "1", "1", "0", str(len(ng)), "5", "RL-DL-20 example",
           "LED downlight, 20 cm, recessed", "RL-DL-20", "downlight.ldt", "2026-12-02 Relume"]
    ldt += ["200", "0", "80", "180", "0", "0", "0", "0", "0", "100", "90", "1", "0"]
    ldt += ["1", "1", "LED module", "%.0f" % LAMP_LM, "3000", "90", "14"]
    ldt += ["0.5"] * 10 + ["0"] + [str(g) for g in ng]
    ldt += ["%.2f" % (candela(g) * 1000.0 / LAMP_LM) for g in ng]
    with open(os.path.join(OUT, "downlight.ldt"), "w") as f:
        f.write("\r\n".join(ldt) + "\r\n")


if __name__ == "__main__":
    main()
