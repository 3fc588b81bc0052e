"""Hand-written SVG plots shared by the bench summarisers (no plotting dependency)."""
import html
import math


def frame(W, H, L, R, T, B, title, xlabel, ylabel):
    """The opening of a plot: the canvas, its title, both axes and their labels (a list of SVG
    elements; the caller appends the data and "</svg>")."""
    return [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="11">',
            f'<rect width="{W}" height="{H}" fill="white"/>',
            f'<text x="{L}" y="18" font-size="13">{html.escape(title)}</text>',
            f'<line x1="{L}" y1="{H-B}" x2="{W-R}" y2="{H-B}" stroke="black"/>',
            f'<line x1="{L}" y1="{T}" x2="{L}" y2="{H-B}" stroke="black"/>',
            f'<text x="{(L+W-R)/2}" y="{H-12}" text-anchor="middle">{html.escape(xlabel)}</text>',
            f'<text x="14" y="{(T+H-B)/2}" transform="rotate(-90 14 {(T+H-B)/2})" text-anchor="middle">{html.escape(ylabel)}</text>']


def log_ticks(l0, l1):
    """Tick values 1, 2, 5 x 10^k between 10^l0 and 10^l1."""
    return [m * 10 ** k for k in range(math.floor(l0), math.ceil(l1) + 1) for m in (1, 2, 5)
            if l0 <= math.log10(m * 10 ** k) <= l1]


def loglog(path, title, xlabel, ylabel, series, guides=(), dashed=(), width=640, legend=210):
    """Log-log plot written to `path`. series: (name, [(x, y)], colour), non-positive points
    dropped; guides: (name, (x0, y0), slope, colour), a dashed line of that slope over the
    decade left of (x0, y0); dashed: (name, y, colour), horizontal lines (noise floors);
    `legend`: the width of the legend column."""
    W, H, L, R, Tm, B = width, 380, 70, legend, 30, 50
    series = [(n, [(x, y) for x, y in pts if x > 0 and y > 0], c) for n, pts, c in series]
    xs = [x for _, pts, _ in series for x, _ in pts]
    ys = [y for _, pts, _ in series for _, y in pts] + [y for _, y, _ in dashed if y > 0]
    if not xs:
        return
    lx0, lx1 = math.log10(min(xs)), math.log10(max(xs))
    ly0, ly1 = math.log10(min(ys)), math.log10(max(ys))
    lx1 = lx1 if lx1 > lx0 else lx0 + 1
    ly0, ly1 = ly0 - 0.05, (ly1 if ly1 > ly0 else ly0 + 1) + 0.05
    sx = lambda v: L + (math.log10(v) - lx0) / (lx1 - lx0) * (W - L - R)  # noqa: E731
    sy = lambda v: H - B - (math.log10(v) - ly0) / (ly1 - ly0) * (H - Tm - B)  # noqa: E731
    o = frame(W, H, L, R, Tm, B, title, xlabel, ylabel)
    for v in log_ticks(lx0, lx1):
        o.append(f'<line x1="{sx(v):.1f}" y1="{H-B}" x2="{sx(v):.1f}" y2="{H-B+4}" stroke="black"/>')
        o.append(f'<text x="{sx(v):.1f}" y="{H-B+15}" text-anchor="middle">{v:g}</text>')
    for v in log_ticks(ly0, ly1):
        o.append(f'<line x1="{L-4}" y1="{sy(v):.1f}" x2="{L}" y2="{sy(v):.1f}" stroke="black"/>')
        o.append(f'<text x="{L-6}" y="{sy(v)+4:.1f}" text-anchor="end">{v:g}</text>')
    k = 0
    for name, pts, colour in series:
        if not pts:
            continue
        d = " ".join(f"{'M' if i == 0 else 'L'}{sx(x):.1f},{sy(y):.1f}" for i, (x, y) in enumerate(pts))
        o.append(f'<path d="{d}" fill="none" stroke="{colour}" stroke-width="1.5"/>')
        for x, y in pts:
            o.append(f'<circle cx="{sx(x):.1f}" cy="{sy(y):.1f}" r="2.2" fill="{colour}"/>')
        o.append(f'<text x="{W-R+8}" y="{Tm+14*k+10}" fill="{colour}">{html.escape(name)}</text>')
        k += 1
    for name, y, colour in dashed:  # horizontal lines (noise floors)
        if y > 0:
            o.append(f'<line x1="{L}" y1="{sy(y):.1f}" x2="{W-R}" y2="{sy(y):.1f}" stroke="{colour}" stroke-dasharray="2,3"/>')
            o.append(f'<text x="{W-R+8}" y="{Tm+14*k+10}" fill="{colour}">{html.escape(name)}</text>')
            k += 1
    for name, (x0, y0), s, colour in guides:
        x1 = x0 / 10
        o.append(f'<line x1="{sx(max(x1, min(xs))):.1f}" y1="{sy(y0 * (max(x1, min(xs)) / x0) ** s):.1f}" '
                 f'x2="{sx(x0):.1f}" y2="{sy(y0):.1f}" stroke="{colour}" stroke-dasharray="5,3"/>')
        o.append(f'<text x="{W-R+8}" y="{Tm+14*k+10}" fill="{colour}">{html.escape(name)}</text>')
        k += 1
    o.append("</svg>")
    open(path, "w").write("\n".join(o))
