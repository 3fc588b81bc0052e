"""Hand-written SVG plots shared by the bench summarisers (no plotting dependency)."""
import html


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
