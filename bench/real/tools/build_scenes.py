#!/usr/bin/python3
"""Writes bench/real/<scene>/ from the public repositories (see ../SOURCES.md).

    /usr/bin/python3 bench/real/tools/build_scenes.py MIRRORS_DIR

MIRRORS_DIR holds bare git clones named owner+name/repo (as `git clone --bare`
would give), at the commits listed in SOURCES.md. Meshes are copied byte for
byte where a scene takes a file as it is; where D consists of several mesh
files of one rigid body (the visuals of one SDF link) they are concatenated
into one binary STL without moving a vertex; the Factory nut and bolt OBJ
files are written as binary PLY (same vertices, same faces, float32). Every
placement is a pose in scene.yaml (static entries' pose:, D's start:), taken
from the source's assembly description as noted in each expected.yaml.
"""
import os, shutil, subprocess, sys
import numpy as np
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshtools as mt

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # bench/real
MIRRORS = sys.argv[1] if len(sys.argv) > 1 else '/work/.mirror'
REPOS = {
    'isaacgymenvs': ('isaac-sim+IsaacGymEnvs/repo', 'aeed298638a1f7b5421b38f5f3cc2d1079b6d9c3', 'LICENSE.txt'),
    'ariac': ('usnistgov+ARIAC/repo', 'ffc825757dc05cc6e4dfbd5c2483e993aab35652', 'LICENSE.md'),
    'agh-scene-props': ('AGH-CEAI+scene_props/repo', 'ebd77c1f59f094b5be9c341cfa9cb54a91e431e5', 'LICENSE.txt'),
    'autodesk-rlroboticassembly': ('AutodeskRoboticsLab+RLRoboticAssembly/repo/.git', '7f72266f626de53762482310f92f6b5c817085b3', 'LICENSE.md'),
}

def blob(src, path):
    d, commit, _ = REPOS[src]
    return subprocess.run(['git', '--git-dir', os.path.join(MIRRORS, d), 'show', f'{commit}:{path}'],
                          check=True, capture_output=True).stdout

def tmpfile(src, path):
    p = os.path.join('/tmp', 'bench-real-src', src, path)
    os.makedirs(os.path.dirname(p), exist_ok=True)
    with open(p, 'wb') as f: f.write(blob(src, path))
    return p

class Scene:
    def __init__(self, name, source):
        self.name, self.source = name, source
        self.dir = os.path.join(HERE, name)
        keep = None   # expected.yaml is written by hand (measured with measure.py): kept
        if os.path.isfile(os.path.join(self.dir, 'expected.yaml')):
            keep = open(os.path.join(self.dir, 'expected.yaml')).read()
        if os.path.isdir(self.dir): shutil.rmtree(self.dir)
        self.keep = keep
        os.makedirs(self.dir)
        with open(os.path.join(self.dir, f'LICENSE-{source}.txt'), 'wb') as f:
            f.write(blob(source, REPOS[source][2]))
    def copy(self, path, name=None, src=None):
        name = name or os.path.basename(path)
        with open(os.path.join(self.dir, name), 'wb') as f: f.write(blob(src or self.source, path))
        return name
    def merge_stl(self, paths, name, src=None):
        T = np.concatenate([mt.load(tmpfile(src or self.source, p)) for p in paths])
        mt.save_stl(os.path.join(self.dir, name), T, name=b'concatenation of ' + ' '.join(os.path.basename(p) for p in paths).encode())
        return name
    def obj_to_ply(self, path, name, src=None):
        V, F = mt.load_indexed_obj(tmpfile(src or self.source, path))
        mt.save_ply(os.path.join(self.dir, name), V, F, comment='from ' + os.path.basename(path))
        return name
    def write(self, scene_yaml, expected_yaml):
        with open(os.path.join(self.dir, 'scene.yaml'), 'w') as f: f.write(scene_yaml)
        with open(os.path.join(self.dir, 'expected.yaml'), 'w') as f: f.write(self.keep or expected_yaml)

def fq(q):  # quaternion, scalar first, as YAML
    return '[' + ', '.join('%.12g' % x for x in q) + ']'
def fv(v):
    return '[' + ', '.join('%.12g' % x for x in v) + ']'

FAC = 'assets/factory/mesh/'
# ---------------------------------------------------------------- Factory (IsaacGymEnvs), metres
def factory_peg(name, peg, hole, units_line, entry_units='', why='', notes=''):
    s = Scene(name, 'isaacgymenvs')
    d = s.copy(FAC + 'factory_insertion/' + peg)
    h = s.copy(FAC + 'factory_insertion/' + hole)
    eu = f', units: {entry_units}' if entry_units else ''
    s.write(f"""format: ausbau-scene/2
name: {name}
units: {units_line}
static:
  - {{file: {h}{eu}}}
dynamic: {{file: {d}{eu}}}
""", '')
    return s

SCENES = []
def scene(fn): SCENES.append(fn); return fn

@scene
def fac_round_4_tight():
    factory_peg('fac-round-peg-4mm-tight', 'factory_round_peg_4mm_tight.obj', 'factory_round_hole_4mm_subdiv_3x.obj', 'm')
@scene
def fac_round_4_loose():
    factory_peg('fac-round-peg-4mm-loose', 'factory_round_peg_4mm_loose.obj', 'factory_round_hole_4mm_subdiv_3x.obj', 'm')
@scene
def fac_round_8_tight_cm():
    factory_peg('fac-round-peg-8mm-tight-cm', 'factory_round_peg_8mm_tight.obj', 'factory_round_hole_8mm_subdiv_3x.obj', 'cm', 'm')
@scene
def fac_rect_8_tight():
    factory_peg('fac-rect-peg-8mm-tight', 'factory_rectangular_peg_8mm_tight_subdiv_3x.obj', 'factory_rectangular_hole_8mm_subdiv_3x.obj', 'm')
@scene
def fac_block_off_peg():
    s = Scene('fac-hole-block-off-peg', 'isaacgymenvs')
    d = s.copy(FAC + 'factory_insertion/factory_round_hole_4mm_subdiv_3x.obj')
    p = s.copy(FAC + 'factory_insertion/factory_round_peg_4mm_tight.obj')
    s.write(f"""format: ausbau-scene/2
name: fac-hole-block-off-peg
units: m
static: [{p}]
dynamic: {d}
""", '')
@scene
def fac_peg_covered():
    s = Scene('fac-peg-covered-both-ends', 'isaacgymenvs')
    d = s.copy(FAC + 'factory_insertion/factory_round_peg_4mm_tight.obj')
    h = s.copy(FAC + 'factory_insertion/factory_round_hole_4mm_subdiv_3x.obj')
    c = s.copy(FAC + 'factory_insertion/factory_rectangular_hole_8mm_subdiv_3x.obj')
    f = s.copy(FAC + 'factory_insertion/factory_round_hole_8mm_subdiv_3x.obj')
    s.write(f"""format: ausbau-scene/2
name: fac-peg-covered-both-ends
units: m
static:
  - {h}
  # a cover on the peg's top face (z = 0.05), shifted 10 mm in x so that its solid part is over the peg
  - {{file: {c}, pose: {{t: [0.010, 0, 0.05], q: [1, 0, 0, 0]}}}}
  # a floor under the peg's bottom face (z = 0), shifted the same way
  - {{file: {f}, pose: {{t: [0.010, 0, -0.0089916], q: [1, 0, 0, 0]}}}}
dynamic: {d}
""", '')
@scene
def fac_nut_bolt():
    s = Scene('fac-nut-m8-on-bolt', 'isaacgymenvs')
    d = s.obj_to_ply(FAC + 'factory_nut_bolt/factory_nut_m8_tight_subdiv_3x.obj', 'factory_nut_m8_tight.ply')
    b = s.obj_to_ply(FAC + 'factory_nut_bolt/factory_bolt_m8_tight.obj', 'factory_bolt_m8_tight.ply')
    s.write(f"""format: ausbau-scene/2
name: fac-nut-m8-on-bolt
units: m
static: [{b}]
dynamic: {d}
""", '')

# ---------------------------------------------------------------- ARIAC (NIST), metres
AR = 'ariac_gazebo/models/'
INSERT = ['insert_base.stl', 'mounts.stl', 'hardware.stl', 'pipe_1.stl', 'pipe_2.stl', 'screen.stl']
ARIAC_PARTS = {  # ariac_gazebo/config/trials/assembly.yaml, products[].assembled_pose (insert frame)
    'regulator': ([0.175, -0.223, 0.215], (np.pi/2, 0, -np.pi/2), ['regulator_base.stl', 'regulator_short_peg.stl', 'regulator_long_peg.stl'], [0, 0, -1]),
    'battery': ([-0.15, 0.035, 0.043], (0, 0, np.pi/2), ['battery_base.stl', 'battery_cap.stl', 'battery_pins.stl'], [0, 1, 0]),
    'pump': ([0.14, 0.0, 0.02], (0, 0, -np.pi/2), ['pump_base.stl', 'pump_enclosure.stl', 'pump_front_pane.stl', 'pump_back_pane.stl',
                                                 'pump_top_pane.stl', 'pump_bottom_pane.stl', 'pump_right_pane.stl', 'pump_left_pane.stl'], [0, 0, -1]),
    'sensor': ([-0.1, 0.395, 0.045], (0, 0, -np.pi/2), ['sensor_base.stl', 'sensor_peg.stl'], [0, -1, 0]),
}
def ariac(part):
    s = Scene(f'ariac-{part}-in-insert', 'ariac')
    xyz, rpy, files, _ = ARIAC_PARTS[part]
    stat = [s.copy(AR + 'assembly_insert/meshes/' + f) for f in INSERT]
    d = s.merge_stl([AR + f'{part}/meshes/' + f for f in files], f'{part}.stl')
    q = mt.quat_rpy(*rpy)
    s.write(f"""format: ausbau-scene/2
name: ariac-{part}-in-insert
units: m
static: [{', '.join(stat)}]
dynamic: {d}
# assembled pose of the {part} in the insert's frame: ARIAC ariac_gazebo/config/trials/assembly.yaml
# (xyz {xyz}, rpy {tuple(round(a, 6) for a in rpy)}, as a quaternion w, x, y, z)
start: {{t: {fv(xyz)}, q: {fq(q)}}}
""", '')
# the battery is left out: its meshes overlap the insert's at the assembled pose and a straight pull
# along -y met them, so its right answer is not known from the geometry without more work
for _p in ('regulator', 'pump', 'sensor'):
    SCENES.append(lambda p=_p: ariac(p))

# ---------------------------------------------------------------- AGH scene_props, millimetres
AG = 'peg_in_hole/meshes/'
@scene
def agh_hex():
    s = Scene('agh-hex-peg-in-block', 'agh-scene-props')
    d = s.copy(AG + 'pegs/6gon_peg.stl'); b = s.copy(AG + 'holes/6gon_box_t5mm.stl')
    s.write(f"""format: ausbau-scene/2
name: agh-hex-peg-in-block
units: mm
static: [{b}]
dynamic: {d}
""", '')
# insertion_box_t5mm.stl: holes (4, 6, 8, 12-gon) centred at y = -90, -30, 30, 90 (holes_array.scad, slot_size 60)
# peg.scad turns an n-gon by (360/n)/2 degrees, holes_array.scad its holes by 0 (4, 6), 22.5 (8), 15 (12):
# the hexagonal peg is turned by 30 degrees about z to fit its hole (the others fit as they are)
AGH_Q = {'4gon_peg.stl': [1, 0, 0, 0], '6gon_peg.stl': [np.cos(np.pi / 12), 0, 0, np.sin(np.pi / 12)],
         '8gon_peg.stl': [1, 0, 0, 0], '12gon_peg.stl': [1, 0, 0, 0]}
AGH_ARRAY = [('4gon_peg.stl', -90), ('6gon_peg.stl', -30), ('8gon_peg.stl', 30), ('12gon_peg.stl', 90)]
@scene
def agh_square_inch():
    s = Scene('agh-square-peg-in-insertion-box-inch', 'agh-scene-props')
    box = s.copy(AG + 'holes/insertion_box_t5mm.stl')
    pegs = [(s.copy(AG + 'pegs/' + f), y) for f, y in AGH_ARRAY]
    lines = [f'  - {{file: {box}, units: mm}}'] + [f'  - {{file: {f}, units: mm, pose: {{t: [0, {y / 25.4:.12g}, 0], q: {fq(AGH_Q[f])}}}}}' for f, y in pegs[1:]]
    st = '\n'.join(lines)
    s.write(f"""format: ausbau-scene/2
name: agh-square-peg-in-insertion-box-inch
units: inch                      # the world in inches; the meshes are in mm (converted by their units:)
static:
{st}
dynamic: {{file: {pegs[0][0]}, units: mm}}
start: {{t: [0, {-90 / 25.4:.12g}, 0], q: [1, 0, 0, 0]}}   # the square peg in the first hole (y = -90 mm)
""", '')
@scene
def agh_box_trapped():
    s = Scene('agh-insertion-box-trapped', 'agh-scene-props')
    d = s.copy(AG + 'holes/insertion_box_t5mm.stl')
    plate = s.copy(AG + 'holes/insertion_box_t10mm.stl')
    pegs = [(s.copy(AG + 'pegs/' + f), y) for f, y in AGH_ARRAY]
    lines = [f'  - {{file: {f}, pose: {{t: [0, {y}, 0], q: {fq(AGH_Q[f])}}}}}' for f, y in pegs]
    lines += [f'  - {{file: {plate}, pose: {{t: [0, 0, -75], q: [1, 0, 0, 0]}}}}   # floor: touches the pegs\' bottom faces (z = -50)',
              f'  - {{file: {plate}, pose: {{t: [0, 0, 75], q: [1, 0, 0, 0]}}}}    # cover: touches the pegs\' top faces (z = 50)']
    st = '\n'.join(lines)
    s.write(f"""format: ausbau-scene/2
name: agh-insertion-box-trapped
units: mm
static:
{st}
dynamic: {d}
""", '')
@scene
def agh_post_held():
    s = Scene('agh-post-held-by-cap', 'agh-scene-props')
    d = s.copy(AG + 'pegs/6gon_peg.stl'); b = s.copy(AG + 'holes/6gon_box_t5mm.stl'); cap = s.copy(AG + 'holes/4gon_box_t5mm.stl')
    s.write(f"""format: ausbau-scene/2
name: agh-post-held-by-cap
units: mm
static:
  - {b}
  - {{file: {cap}, pose: {{t: [0, 0, 75], q: [1, 0, 0, 0]}}}}    # cap on the post's top face (z = 50); its square hole is narrower than the post
  - {{file: {cap}, pose: {{t: [0, 0, -75], q: [1, 0, 0, 0]}}}}   # the same block under the post's bottom face (z = -50)
dynamic: {d}
""", '')
@scene
def agh_cap_on_post():
    s = Scene('agh-cap-on-post', 'agh-scene-props')
    d = s.copy(AG + 'holes/4gon_box_t5mm.stl'); b = s.copy(AG + 'holes/6gon_box_t5mm.stl'); post = s.copy(AG + 'pegs/6gon_peg.stl')
    s.write(f"""format: ausbau-scene/2
name: agh-cap-on-post
units: mm
static: [{b}, {post}]
dynamic: {d}
start: {{t: [0, 0, 75], q: [1, 0, 0, 0]}}   # the cap rests on the post's top face (z = 50)
""", '')

# ---------------------------------------------------------------- Autodesk RLRoboticAssembly, millimetres
AD = 'envs/urdf/panda_peg_in_hole/stl/visual/'
@scene
def adsk_peg():
    s = Scene('adsk-square-peg-through-box', 'autodesk-rlroboticassembly')
    d = s.copy(AD + 'peg.stl'); b = s.copy(AD + 'insertion_box.stl')
    # peg.stl: a square prism along z, its section turned 33.1576 degrees about z (panda_peg.urdf turns it
    # back by its yaw 0.57 rad) and centred at (0.0884, 0.4316). Turn it by -33.1576 deg about z, then its
    # axis onto +y (-90 deg about x), and centre it in the box's larger hole (x 30.225..66.795, z 24.9..61.2;
    # robot_sim_panda.py HOLE_OFFSET = [0.048485, -0.04305, ...]), its flat end 20 mm beyond the face y = 67.
    a = np.radians(-33.157620)
    qz = np.array([np.cos(a / 2), 0, 0, np.sin(a / 2)])
    qx = np.array([np.cos(-np.pi / 4), np.sin(-np.pi / 4), 0, 0])
    q = mt.qmul(qx, qz)
    c = mt.qmat(q) @ np.array([0.0883860, 0.4316075, 81.8587])
    t = np.array([48.51, 67 + 20, 43.05]) - c
    s.write(f"""format: ausbau-scene/2
name: adsk-square-peg-through-box
units: mm
static: [{b}]
dynamic: {d}
start: {{t: {fv(t)}, q: {fq(q)}}}
""", '')

if __name__ == '__main__':
    only = sys.argv[2:]
    for fn in SCENES:
        fn()
