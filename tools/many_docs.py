"""Write the benchmark documents of many small parts into DIR (the same files every run:
seeded): session 17's many-layer family (markers with and without a blur, drop-shadowed
boxes, clipped groups, opacity and mask groups), 2000 text labels, 1000 dashed cubics and
300 dashed circles; faded and clipped groups of 1 and 3 shapes, 3000 small paths with
`opacity` and their twin with `fill-opacity` (session 21). docs/bench.md's session 20 and 21
sections time them.

    python tools/many_docs.py DIR
"""
import math, os, random, sys
out = sys.argv[1]; os.makedirs(out, exist_ok=True)
HEAD = '<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="1000" viewBox="0 0 1000 1000">\n'
def w(name, body):
    open(os.path.join(out, name + '.svg'), 'w').write(HEAD + body + '</svg>\n')
R = random.Random(17)
pts = ' '.join(f'{R.uniform(0,1000):.1f},{R.uniform(0,1000):.1f}' for _ in range(20002))
w('markers_blur', '<defs><filter id="b" x="-50%" y="-50%" width="200%" height="200%"><feGaussianBlur stdDeviation="0.8"/></filter>'
  '<marker id="m" markerUnits="userSpaceOnUse" markerWidth="8" markerHeight="8" refX="4" refY="4">'
  '<circle cx="4" cy="4" r="3" fill="teal" filter="url(#b)"/></marker></defs>\n'
  f'<polyline points="{pts}" fill="none" stroke="#888" stroke-width="0.3" marker-mid="url(#m)"/>\n')
R = random.Random(18)
pts = ' '.join(f'{R.uniform(0,1000):.1f},{R.uniform(0,1000):.1f}' for _ in range(5002))
w('markers_plain', '<defs><marker id="m" markerUnits="userSpaceOnUse" markerWidth="8" markerHeight="8" refX="4" refY="4">'
  '<circle cx="4" cy="4" r="3" fill="teal"/><path d="M1 4 L7 4" stroke="black" stroke-width="0.8"/></marker></defs>\n'
  f'<polyline points="{pts}" fill="none" stroke="#888" stroke-width="0.3" marker-mid="url(#m)"/>\n')
def boxes(n, seed):
    R = random.Random(seed)
    s = ['<defs><filter id="sh" x="-20%" y="-20%" width="160%" height="160%">'
         '<feGaussianBlur in="SourceAlpha" stdDeviation="2"/><feOffset dx="2" dy="2" result="o"/>'
         '<feFlood flood-color="black" flood-opacity="0.5"/><feComposite in2="o" operator="in"/>'
         '<feMerge><feMergeNode/><feMergeNode in="SourceGraphic"/></feMerge></filter></defs>']
    for _ in range(n):
        x, y = R.uniform(0, 960), R.uniform(0, 975)
        s.append(f'<g filter="url(#sh)"><rect x="{x:.1f}" y="{y:.1f}" width="36" height="22" rx="4" fill="#{R.randrange(1<<24):06x}"/>'
                 f'<path d="M{x+4:.1f} {y+11:.1f} h28" stroke="white" stroke-width="2"/></g>')
    return '\n'.join(s) + '\n'
w('boxes_shadow_500', boxes(500, 19)); w('boxes_shadow_2000', boxes(2000, 20))
R = random.Random(21); s = []
for i in range(2000):
    x, y = R.uniform(0, 960), R.uniform(0, 960)
    s.append(f'<clipPath id="c{i}"><circle cx="{x+20:.1f}" cy="{y+20:.1f}" r="18"/></clipPath>'
             f'<g clip-path="url(#c{i})"><rect x="{x:.1f}" y="{y:.1f}" width="40" height="40" fill="#{R.randrange(1<<24):06x}"/>'
             f'<path d="M{x:.1f} {y:.1f} L{x+40:.1f} {y+40:.1f}" stroke="black" stroke-width="3"/></g>')
w('symbols_clip', '\n'.join(s) + '\n')
R = random.Random(22); s = ['<clipPath id="c" clipPathUnits="objectBoundingBox"><circle cx="0.5" cy="0.5" r="0.5"/></clipPath>']
for i in range(2000):
    s.append(f'<rect clip-path="url(#c)" x="{R.uniform(0,960):.1f}" y="{R.uniform(0,960):.1f}" width="40" height="40" fill="#{R.randrange(1<<24):06x}"/>')
w('symbols_clip_bbox', '\n'.join(s) + '\n')
R = random.Random(23); s = []
for i in range(1000):
    x, y = R.uniform(0, 960), R.uniform(0, 970)
    s.append(f'<g opacity="0.6"><rect x="{x:.1f}" y="{y:.1f}" width="40" height="30" fill="#{R.randrange(1<<24):06x}"/>'
             f'<circle cx="{x+30:.1f}" cy="{y+20:.1f}" r="12" fill="#{R.randrange(1<<24):06x}"/></g>')
w('groups_opacity', '\n'.join(s) + '\n')
R = random.Random(24); s = ['<mask id="k" maskContentUnits="objectBoundingBox"><rect width="1" height="1" fill="white" opacity="0.7"/>'
     '<circle cx="0.5" cy="0.5" r="0.3" fill="black"/></mask>']
for i in range(1000):
    x, y = R.uniform(0, 960), R.uniform(0, 970)
    s.append(f'<g mask="url(#k)"><rect x="{x:.1f}" y="{y:.1f}" width="40" height="30" fill="#{R.randrange(1<<24):06x}"/>'
             f'<circle cx="{x+30:.1f}" cy="{y+20:.1f}" r="12" fill="#{R.randrange(1<<24):06x}"/></g>')
w('groups_mask', '\n'.join(s) + '\n')
R = random.Random(25); s = []
words = 'Alexandria Harbour Street Avenue Market Station Park Museum Library Gate North South'.split()
for i in range(2000):
    s.append(f'<text x="{R.uniform(0,900):.1f}" y="{R.uniform(10,1000):.1f}" font-family="sans-serif" font-size="{R.choice((8,9,10,12))}" '
             f'fill="#333">{R.choice(words)} {R.choice(words)} {R.randrange(1,200)}</text>')
w('labels_2000', '\n'.join(s) + '\n')
R = random.Random(26); s = []
for i in range(1000):
    p = [R.uniform(0, 1000) for _ in range(8)]
    s.append(f'<path d="M{p[0]:.1f} {p[1]:.1f} C{p[2]:.1f} {p[3]:.1f} {p[4]:.1f} {p[5]:.1f} {p[6]:.1f} {p[7]:.1f}" fill="none" stroke="#{R.randrange(1<<24):06x}" stroke-width="2" stroke-dasharray="6 3 1 3"/>')
w('dashed_curves_1000', '\n'.join(s) + '\n')
R = random.Random(27); s = []
for i in range(300):
    s.append(f'<circle cx="{R.uniform(0,1000):.1f}" cy="{R.uniform(0,1000):.1f}" r="{R.uniform(5,60):.1f}" fill="none" stroke="navy" stroke-width="1.5" stroke-dasharray="4 2"/>')
w('dashed_circles_300', '\n'.join(s) + '\n')
# 4000 small stars and discs in groups of k, each group faded (opacity) or clipped by a disc:
# the items a band grows as k shrinks (session 21's band threads)
for k in (1, 3):
    for kind in ('faded', 'clipped'):
        R = random.Random(100 + k); s = []
        for g in range(4000 // k):
            cx, cy = R.uniform(50, 950), R.uniform(50, 950)
            if kind == 'clipped':
                s.append(f'<clipPath id="c{g}"><circle cx="{cx:.1f}" cy="{cy:.1f}" r="{R.uniform(20, 80):.1f}"/></clipPath><g clip-path="url(#c{g})">')
            else:
                s.append('<g opacity="0.7">')
            for i in range(k):
                x, y, r = cx + R.uniform(-60, 60), cy + R.uniform(-60, 60), R.uniform(5, 40)
                pts = ' '.join(f'{x + r * math.cos(math.pi * j / 6) * (1 if j % 2 else .5):.1f},'
                               f'{y + r * math.sin(math.pi * j / 6) * (1 if j % 2 else .5):.1f}' for j in range(12))
                s.append(f'<polygon points="{pts}" fill="#{R.randrange(1<<24):06x}"/>'
                         f'<circle cx="{x:.1f}" cy="{y:.1f}" r="{r / 3:.1f}" fill="#{R.randrange(1<<24):06x}"/>')
            s.append('</g>')
        w(f'{kind}_groups_k{k}', '\n'.join(s) + '\n')
for name, attr in (('paths_opacity', 'opacity'), ('paths_fill_opacity', 'fill-opacity')):
    R = random.Random(21); s = []
    for i in range(3000):
        x, y = R.uniform(0, 960), R.uniform(0, 960)
        p = [R.uniform(0, 40) for _ in range(6)]
        s.append(f'<path d="M{x:.1f} {y:.1f} q{p[0]:.1f} {p[1]:.1f} {p[2]:.1f} {p[3]:.1f} l{p[4]-20:.1f} {p[5]:.1f} z" '
                 f'fill="#{R.randrange(1<<24):06x}" {attr}=".5"/>')
    w(name, '\n'.join(s) + '\n')
