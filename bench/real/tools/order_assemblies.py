#!/usr/bin/env python3
"""Writes the real-mesh assemblies of the disassembly-order benchmark
(scripts/order-bench.sh): one binary STL per part, in its assembled pose
(the poses of the bench/real scenes they come from, the meshes unchanged
otherwise), into OUT/<assembly>/parts/, and OUT/<assembly>/expected.txt:
the fixed part on the first line, then one line per step of the order the
geometry gives (its parts, sorted, space-separated).

    order_assemblies.py OUT
"""
import os, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshtools as mt

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # bench/real
IDENTITY = ([1, 0, 0, 0], [0, 0, 0])

# name: (scene folder, [(part, mesh file, (q, t))], fixed part, steps)
ASSEMBLIES = {
    # A hexagonal post through a block (the frame), a cap on its top face and
    # the same block under its bottom face, each with a square hole narrower
    # than the post: both caps come off (up, down), then the post.
    'agh-post-two-caps': ('agh-post-held-by-cap', [
        ('block', '6gon_box_t5mm.stl', IDENTITY),
        ('post', '6gon_peg.stl', IDENTITY),
        ('cap_top', '4gon_box_t5mm.stl', ([1, 0, 0, 0], [0, 0, 75])),
        ('cap_bottom', '4gon_box_t5mm.stl', ([1, 0, 0, 0], [0, 0, -75])),
    ], 'block', [['cap_bottom', 'cap_top'], ['post']]),
}

# Not run yet: the parts of agh-insertion-box-trapped (an insertion box on
# four posts in its holes, a plate on the posts from above and one under
# them, the floor fixed; order: cover, the four posts, the box). The cover's
# straight pulls, sliding over the posts' top faces, which touch its bottom
# face exactly, did not end within 15 minutes (2026-12-04): the surface
# depth of coincident faces beside a hole's outline is refined to its floor.
# Kept here to be added back once that is fixed.
UNFINISHED = {
    # An insertion box on four posts in its holes, a plate on the posts from
    # above and one under them (the frame): the cover lifts off, then the
    # posts come up out of the box's holes, then the box.
    'agh-box-on-four-posts': ('agh-insertion-box-trapped', [
        ('floor', 'insertion_box_t10mm.stl', ([1, 0, 0, 0], [0, 0, -75])),
        ('cover', 'insertion_box_t10mm.stl', ([1, 0, 0, 0], [0, 0, 75])),
        ('peg4', '4gon_peg.stl', ([1, 0, 0, 0], [0, -90, 0])),
        ('peg6', '6gon_peg.stl', ([0.965925826289, 0, 0, 0.258819045103], [0, -30, 0])),
        ('peg8', '8gon_peg.stl', ([1, 0, 0, 0], [0, 30, 0])),
        ('peg12', '12gon_peg.stl', ([1, 0, 0, 0], [0, 90, 0])),
        ('box', 'insertion_box_t5mm.stl', IDENTITY),
    ], 'floor', [['cover'], ['peg12', 'peg4', 'peg6', 'peg8'], ['box']]),
}

def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    for name, (scene, parts, fixed, steps) in ASSEMBLIES.items():
        folder = os.path.join(out, name, 'parts')
        os.makedirs(folder, exist_ok=True)
        for part, mesh, (q, t) in parts:
            T = mt.load(os.path.join(HERE, scene, mesh))
            mt.save_stl(os.path.join(folder, part + '.stl'), mt.place(T, q, t))
        with open(os.path.join(out, name, 'expected.txt'), 'w') as f:
            f.write(fixed + '\n')
            for step in steps:
                f.write(' '.join(sorted(step)) + '\n')
        print(name)

if __name__ == '__main__':
    main()
