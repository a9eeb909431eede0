#!/usr/bin/env python3
"""`./rome figures` from short runs: examples/figures/rome_figures.sh --quick must write every figure the three papers'
reproduction lists (issue 44), each a PNG that shows drawn data above its caption. Checks, each with its source:

1. the script exits 0 and every expected file exists: the list below is the papers' figures (stepping stones Figs. 4,
   5, 6a, 6b, 7 for both robots where the paper shows both; walking Figs. 2, 3, 5; hopping Fig. 6a-f), written here
   from the papers, not read from the script;
2. each PNG decodes (signature, IHDR, zlib-inflated IDAT, every scanline's filter undone: the PNG specification's
   filters 0-4) to width x height pixels;
3. the figure is not blank: in the plot area (above the caption strip) at least MIN_INK of the pixels differ from the
   background colour (the most common one), and at least MIN_COLOURED pixels are coloured (max - min channel >= 60:
   a data line, not the black axes, the grey grid or the white background; every figure draws its data in colour);
4. captions.txt of each paper names the paper's figure of each PNG ("Fig. N").
Check 3 is first shown to fail: on an all-white PNG and on gnuplot's axes and grid without data (drawn by the test).

usage: figures_test.py ROME_FIGURES_SH BIN_DIR WORK_DIR   (run from the repository root)
"""
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

MIN_INK = 0.005  # fraction of the plot area's pixels that are not background
MIN_COLOURED = 200  # pixels of a coloured data line

EXPECTED = {
    "stepping-stones": [f"fig4_{t}_{r}_gait_tiles.png" for r in ("amber", "cassie_planar")
                        for t in ("flat", "stairs-up", "stairs-down")]
    + [f"fig5_{r}_{p}.png" for r in ("amber", "cassie_planar") for p in ("outputs", "pre_impact_vz")]
    + ["fig6a_speed_over_step_length.png", "fig6b_speed_over_energy.png"]
    + [f"fig7_{r}_{p}.png" for r in ("amber", "cassie_planar") for p in ("gait_tiles", "com_height", "phase_portrait")],
    "walking": ["fig2_s2_aslip_periodic.png", "fig2_l2_hlip_p2_portrait.png", "fig3_s2_transition_sagittal.png",
                "fig3_l2_transition_lateral.png", "fig5a_com.png", "fig5b_com_velocity.png",
                "fig5c_gait_tiles_sagittal.png", "fig5c_gait_tiles_frontal.png", "fig5d_normal_forces.png"],
    "hopping": ["fig6ab_output_leg_length.png", "fig6ab_output_com_x.png", "fig6ab_output_pitch.png", "fig6c_energy.png",
                "fig6d_spring_torque.png", "fig6e_pitch_momentum.png", "fig6f_grf.png"],
}


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else (b if pb <= pc else c)


def decode_png(path):
    """(width, height, rows of RGB tuples) of an 8-bit RGB, RGBA, grey or palette PNG, not interlaced."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("no PNG signature")
    pos, idat, palette, header = 8, b"", None, None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"PLTE":
            palette = [tuple(body[i:i + 3]) for i in range(0, len(body), 3)]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    w, h, depth, colour, _, _, interlace = header
    channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[colour]
    if depth != 8 or interlace:
        raise ValueError(f"unsupported PNG (bit depth {depth}, interlace {interlace})")
    raw, stride, bpp = zlib.decompress(idat), w * channels, channels
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            line[i] = (line[i] + (0, a, b, (a + b) // 2, paeth(a, b, c))[f]) & 0xFF
        prev = line
        if colour == 3:
            rows.append([palette[v] for v in line])
        elif colour in (0, 4):
            rows.append([(line[i],) * 3 for i in range(0, stride, channels)])
        else:
            rows.append([tuple(line[i:i + 3]) for i in range(0, stride, channels)])
    return w, h, rows


def check_png(path):
    w, h, rows = decode_png(path)
    if len(rows) != h or any(len(r) != w for r in rows):
        return f"{w} x {h} declared, {len(rows)} rows decoded"
    counts = {}
    for r in rows:
        for p in r:
            counts[p] = counts.get(p, 0) + 1
    background = max(counts, key=counts.get)
    plot = rows[:h - 60]  # above the caption strip (at least 2 text lines: 45 px)
    ink = sum(p != background for r in plot for p in r) / float(w * len(plot))
    coloured = sum(max(p) - min(p) >= 60 for r in plot for p in r)
    problems = []
    if ink < MIN_INK:
        problems.append(f"blank: {100 * ink:.2f} % of the plot area differs from the background (expected >= {100 * MIN_INK} %)")
    if coloured < MIN_COLOURED:
        problems.append(f"no data drawn: {coloured} coloured pixels (expected >= {MIN_COLOURED})")
    return "; ".join(problems)


def blank_pngs_fail(work):
    """The check must fail on a white image and on axes without data, both 900 x 546 px as the figures (gnuplot)."""
    script = ("set terminal pngcairo size 900,546\nset output '{0}/white.png'\nunset border; unset tics; unset key\n"
              "plot [0:1][0:1] 1/0\nset output '{0}/axes.png'\nset border; set tics; set grid; set key\n"
              "set title 'no data'; set xlabel 't [s]'; plot [0:1][0:1] 1/0 title 'nothing'\n").format(work)
    subprocess.run(["gnuplot"], input=script, text=True, check=True, capture_output=True)
    return [f"the check passes the data-free {name}" for name in ("white.png", "axes.png")
            if not check_png(os.path.join(work, name))]


def main():
    script, bin_dir, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    failures = blank_pngs_fail(work)
    figures = os.path.join(work, "figures")
    run = subprocess.run(["bash", script, bin_dir, figures, "--quick"], capture_output=True, text=True)
    if run.returncode != 0:
        failures.append(f"rome_figures.sh --quick exited {run.returncode}: {run.stderr.strip()[-600:]}")
    for paper, files in EXPECTED.items():
        captions = ""
        if os.path.exists(os.path.join(figures, paper, "captions.txt")):
            captions = open(os.path.join(figures, paper, "captions.txt")).read()
        for name in files:
            path = os.path.join(figures, paper, name)
            if not os.path.isfile(path):
                failures.append(f"{paper}/{name}: not written")
                continue
            try:
                problem = check_png(path)
            except (ValueError, KeyError, zlib.error, struct.error, TypeError) as e:
                problem = f"not a decodable PNG ({e})"
            if problem:
                failures.append(f"{paper}/{name}: {problem}")
            figure = "Fig. " + re.match(r"fig(\d+)", name).group(1)
            line = next((l for l in captions.splitlines() if l.startswith(name + "\t")), "")
            if figure not in line:
                failures.append(f"{paper}/{name}: captions.txt has no caption naming {figure}: '{line[:120]}'")
    for f in failures:
        print("FAIL: " + f)
    if not failures:
        print(f"{sum(len(v) for v in EXPECTED.values())} figures written, decoded and not blank")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
