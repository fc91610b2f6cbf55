"""SVG charts for the performance report (standard library only): values per scene (categories on x)
and y against x (both numeric). A legend on the right; a series keeps its colour in every chart when
the caller names its colour (`colours`: name -> colour); an axis goes logarithmic when its data spans a
factor of 10 or more, so decades of frame time stay readable.
Points whose value is None are skipped; a chart without any point is None."""
import math
from xml.sax.saxutils import escape

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#7f7f7f"]
LEFT, TOP = 80, 44


class Axis:
    """Maps data to pixels over [lo, hi]; log10 when the data spans a decade or more."""

    def __init__(self, values, pixel_from, pixel_to, force_log=None, include=()):
        values = [v for v in list(values) + list(include) if v is not None and v > 0]
        lo, hi = min(values), max(values)
        self.log = force_log if force_log is not None else hi / lo >= 10
        if self.log:
            self.lo, self.hi = 10 ** math.floor(math.log10(lo)), 10 ** math.ceil(math.log10(hi))
            if self.hi / self.lo < 100:  # at most one decade shown: tighten to 1-2-5 steps
                self.lo, self.hi = _step_below(lo), _step_above(hi)
        else:
            step = _nice_step(hi / 5)
            self.lo, self.hi = 0.0, step * math.ceil(hi / step * 1.05)
        self.p0, self.p1 = pixel_from, pixel_to

    def __call__(self, v):
        if self.log:
            f = math.log10(v / self.lo) / math.log10(self.hi / self.lo)
        else:
            f = (v - self.lo) / (self.hi - self.lo)
        return self.p0 + f * (self.p1 - self.p0)

    def ticks(self):
        if not self.log:
            step = _nice_step((self.hi - self.lo) / 5)
            return [self.lo + i * step for i in range(int(round((self.hi - self.lo) / step)) + 1)]
        decades = range(round(math.log10(self.lo)), round(math.log10(self.hi)) + 1)
        mults = (1,) if self.hi / self.lo >= 1000 else (1, 2, 5)
        return [m * 10 ** d for d in decades for m in mults if self.lo * 0.999 <= m * 10 ** d <= self.hi * 1.001]


def _nice_step(raw):
    base = 10 ** math.floor(math.log10(raw))
    return next(m * base for m in (1, 2, 5, 10) if m * base >= raw)


def _step_below(v):
    base = 10 ** math.floor(math.log10(v))
    return max(m * base for m in (1, 2, 5) if m * base <= v)


def _step_above(v):
    base = 10 ** math.floor(math.log10(v))
    return min(m * base for m in (1, 2, 5, 10) if m * base >= v)


def _label(v):
    return "%g" % v if v >= 0.01 or v == 0 else "%.0e" % v


def _frame(width, right, height, bottom, title, x_label, y_label, y_axis):
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
           'font-family="sans-serif" font-size="12">' % (width, height, width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="24" font-size="15" font-weight="bold">%s</text>' % (LEFT, escape(title))]
    for t in y_axis.ticks():
        y = y_axis(t)
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (LEFT, y, width - right, y))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%s</text>' % (LEFT - 6, y + 4, _label(t)))
    out.append('<rect x="%d" y="%d" width="%d" height="%d" fill="none" stroke="#444"/>'
               % (LEFT, TOP, width - LEFT - right, height - TOP - bottom))
    out.append('<text x="%d" y="%d" text-anchor="middle">%s</text>' % ((LEFT + width - right) / 2, height - 8,
                                                                         escape(x_label)))
    out.append('<text transform="translate(18 %d) rotate(-90)" text-anchor="middle">%s%s</text>'
               % ((TOP + height - bottom) / 2, escape(y_label), " (log scale)" if y_axis.log else ""))
    return out


def _legend_width(series):
    """The right margin that holds the legend: its longest name at about 7 px a character."""
    return 48 + 7 * max(len(name) for name, _ in series)


def _colour(colours, name, k):
    return (colours or {}).get(name) or COLOURS[k % len(COLOURS)]


def _legend(out, width, right, names, colours):
    for i, name in enumerate(names):
        y = TOP + 12 + 20 * i
        colour = _colour(colours, name, i)
        out.append('<rect x="%d" y="%d" width="14" height="10" fill="%s"/>' % (width - right + 12, y - 8, colour))
        out.append('<text x="%d" y="%d">%s</text>' % (width - right + 32, y + 2, escape(name)))


def _reference(out, width, right, y_axis, value):
    if value is not None and y_axis.lo <= value <= y_axis.hi:
        y = y_axis(value)
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#000" stroke-dasharray="6 4"/>'
                   % (LEFT, y, width - right, y))


def category_plot(title, categories, series, y_label, reference=None, colours=None):
    """series: [(name, [value per category])]. Each series' markers sit side by side within a category."""
    values = [v for _, vs in series for v in vs if v]
    if not values or not categories:
        return None
    right = _legend_width(series)
    width = LEFT + right + max(440, 56 * len(categories))
    bottom = 40 + 6 * max(len(c) for c in categories)  # room for the slanted scene names
    height = TOP + 300 + bottom
    y = Axis(values, TOP + 300, TOP, include=[reference] if reference else ())
    out = _frame(width, right, height, bottom, title, "scene", y_label, y)
    band = (width - LEFT - right) / len(categories)
    for i, name in enumerate(categories):
        x = LEFT + band * (i + 0.5)
        out.append('<text transform="translate(%.1f %d) rotate(-35)" text-anchor="end">%s</text>'
                   % (x + 4, TOP + 300 + 16, escape(name)))
        if i:
            out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#eee"/>'
                       % (LEFT + band * i, TOP, LEFT + band * i, TOP + 300))
    _reference(out, width, right, y, reference)
    for k, (name, vs) in enumerate(series):
        colour = _colour(colours, name, k)
        offset = (k - (len(series) - 1) / 2) * min(6.0, band * 0.8 / max(1, len(series)))
        for i, v in enumerate(vs):
            if v:
                out.append('<circle cx="%.1f" cy="%.1f" r="4" fill="%s"/>' % (LEFT + band * (i + 0.5) + offset, y(v),
                                                                               colour))
    _legend(out, width, right, [n for n, _ in series], colours)
    return "\n".join(out + ["</svg>"]) + "\n"


def xy_plot(title, series, x_label, y_label, colours=None):
    """series: [(name, [(x, y), ...])], drawn as lines with markers."""
    pts = [(x, v) for _, s in series for x, v in s if v]
    if len(pts) < 2:
        return None
    right = _legend_width(series)
    width, height, bottom = LEFT + right + 540, 440, 50
    xa = Axis([p[0] for p in pts], LEFT, width - right)
    ya = Axis([p[1] for p in pts], height - bottom, TOP)
    out = _frame(width, right, height, bottom, title, x_label + (" (log scale)" if xa.log else ""), y_label, ya)
    for t in xa.ticks():
        out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (xa(t), TOP, xa(t), height - bottom))
        out.append('<text x="%.1f" y="%d" text-anchor="middle">%s</text>' % (xa(t), height - bottom + 16, _label(t)))
    for k, (name, s) in enumerate(series):
        colour = _colour(colours, name, k)
        good = [(xa(x), ya(v)) for x, v in s if v]
        if len(good) > 1:
            out.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>'
                       % (colour, " ".join("%.1f,%.1f" % p for p in good)))
        out += ['<circle cx="%.1f" cy="%.1f" r="4" fill="%s"/>' % (px, py, colour) for px, py in good]
    _legend(out, width, right, [n for n, _ in series], colours)
    return "\n".join(out + ["</svg>"]) + "\n"
