#!/usr/bin/env python3
"""Which term sets a regions group's map side, and what halving the sides costs (penumbra.analysis.regions):
  python3 texels.py terms RUN_DIR... > texel-terms.csv            render folders of regions:target=T
  python3 texels.py halve OUT [--resolution 128] [--map 1024] > halved.csv   each (scene, T) as decided,
      every group's side halved (density D/2, max_size halved) and quartered (D/4, a quarter) (PENUMBRA=bin)
  python3 texels.py map-error halved.csv RUN_DIR... > map-error.csv"""
import argparse, os, sys
from penumbra.analysis import binary, read, read_json, regions as r, write_csv
from penumbra.analysis.engine import method_params

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument('command', choices=['terms', 'halve', 'map-error'])
p.add_argument('files', nargs='+')
p.add_argument('--resolution', type=int, default=128)
p.add_argument('--map', type=int, default=1024)
p.add_argument('--scenes', default='canopy-market,pergola-garden,default')
p.add_argument('--targets', default='0.03,0.02,0.012')
a = p.parse_intermixed_args()
if a.command == 'terms':
    write_csv(sys.stdout, r.TEXEL_TERMS_HEADER, [row for d in a.files for row in r.texel_terms(read_json(os.path.join(d, 'run.json')))])
elif a.command == 'map-error':
    halved = read(a.files[0])
    write_csv(sys.stdout, r.MAP_ERROR_HEADER, [row for d in a.files[1:] for row in [r.map_error(halved, read_json(os.path.join(d, 'run.json')))] if row])
else:
    bin_, rows, sets = binary.find(), [], {'resolution': a.resolution, 'shadow_map_size': a.map}
    top = method_params('regions')['max_size']
    for s in a.scenes.split(','):
        for t in a.targets.split(','):
            d = os.path.join(a.files[0], f'{s}-{t}')
            # The plan's own texel rule: certify=off (regions' certified classes step sides up after it).
            first = binary.render(bin_, s, f'regions:target={t},certify=off', os.path.join(d, 'r1'), sets)
            if not first.ok:
                sys.exit(f'{s} {t}: {first.last_line()}')
            D = first.run_json().number('method_record.density')
            methods = [f'regions:target={t},certify=off', f'regions:target={t},certify=off,density={D / 2},max_size={top // 2}', f'regions:target={t},certify=off,density={D / 4},max_size={top // 4}']
            cmp = binary.compare(bin_, s, methods, os.path.join(d, 'cmp'), sets, 1)
            runs = [first] + [binary.render(bin_, s, m, os.path.join(d, f'r{i + 1}'), sets) for i, m in enumerate(methods[1:], 1)]
            if not cmp.ok or not all(x.ok for x in runs):
                sys.exit(f'{s} {t}: {cmp.last_line() if not cmp.ok else next(x.last_line() for x in runs if not x.ok)}')
            for row, run, name in zip(cmp.results(), runs, ['as decided', 'halved', 'quartered']):
                m = run.run_json().raw('method_record')
                rows.append([s, t, name, row.integer('maps'), round(row.number('rmse'), 5), round(m['density'], 2), r.groups_label(m)])
    write_csv(sys.stdout, r.HALVED_HEADER, rows)
