#!/usr/bin/env python3
"""Writes each harness's seed inputs into OUT/NAME/ from config/, a few inputs of our own, and
the shared corpus when it is there (read at run time, never copied into the repository). A clone
with no corpus beside it gets every harness seeded all the same."""
import glob, json, os, re, struct, sys

src, corpus, out = sys.argv[1], sys.argv[2], sys.argv[3]
seeds = {}
if not os.path.isdir(corpus) or not os.listdir(corpus):
    print(f'seeds: no shared corpus at {corpus}: seeds from config/ and our own inputs only', file=sys.stderr)

def corpus_json(rel):
    """A JSON file of the corpus, or None when the corpus (or that file) is not here."""
    p = os.path.join(corpus, rel)
    if not os.path.isfile(p):
        return None
    with open(p) as f:
        return json.load(f)

def add(name, data):
    if isinstance(data, str):
        data = data.encode()
    seeds.setdefault(name, []).append(data)

def read(p):
    with open(p, 'rb') as f:
        return f.read()

def hexbytes(text):
    return bytes(int(t, 16) for t in re.findall(r'\b[0-9a-fA-F]{2}\b', text))

# SVG documents, path data, attribute values, colours, style sheets.
# Text (tspans, anchors, spacing, preserved white space, a textPath), which no character has.
add('fuzz_svg_document', b'''<svg xmlns="http://www.w3.org/2000/svg" width="120" height="80">
<text x="10 20" y="30" dx="1" font-family="DejaVu Sans, serif" font-size="12" font-weight="bold" letter-spacing="1">Hi <tspan
 x="40" dy="-2" fill="#c00" font-style="italic" text-anchor="middle">there</tspan><a><tspan>!</tspan></a></text>
<text x="60" y="70" text-anchor="end" xml:space="preserve" stroke="#000" font-size="2em">  a	b  <textPath href="#p">x</textPath></text>
</svg>''')
svgs = sorted(glob.glob(f'{src}/config/characters/*.svg'))
svgs += sorted(glob.glob(f'{corpus}/svg/characters-dicebear-cc0/*.svg'))
svgs += sorted(glob.glob(f'{corpus}/svg/resvg/**/*.svg', recursive=True))[::12]
svgs += sorted(glob.glob(f'{corpus}/svg/w3c-svg11-2e/**/*.svg', recursive=True))[::8]
for p in svgs:
    data = read(p)
    if len(data) <= 65536:
        add('fuzz_svg_document', data)
    text = data.decode('utf-8', 'replace')
    for d in re.findall(r'\sd="([^"]{1,4000})"', text)[:4]:
        add('fuzz_svg_path', d)
    for v in re.findall(r'(?:transform|points|viewBox|width|x|opacity)="([^"]{1,400})"', text)[:6]:
        add('fuzz_svg_values', v)
    for c in re.findall(r'(?:fill|stroke|stop-color)[=:]\s*"?([^";>]{1,60})', text)[:6]:
        add('fuzz_color', c)
    for s in re.findall(r'<style[^>]*>(.{1,4000}?)</style>', text, re.S)[:2]:
        add('fuzz_css', s.replace('<![CDATA[', '').replace(']]>', '') + '\0shape')
    for s in re.findall(r'style="([^"]{1,400})"', text)[:2]:
        add('fuzz_css', s)

# Rigs, shows, device profiles (TOML).
for p in sorted(glob.glob(f'{src}/config/rigs/*.toml')):
    add('fuzz_rig_toml', read(p))
for p in sorted(glob.glob(f'{src}/config/shows/*.toml')):
    add('fuzz_show_toml', read(p))
    for script in re.findall(rb'script = """\n(.*?)"""', read(p), re.S):
        for kind in range(4):
            add('fuzz_timeline', bytes([kind | 0x80]) + script)
for p in sorted(glob.glob(f'{src}/config/devices/*.toml')):
    add('fuzz_device_profile', read(p))

# MIDI 1.0 streams and USB-MIDI packets: our own few (note on/off with running status, a
# controller, a SysEx, real-time bytes inside a message), then the corpus's parser vectors.
for s in ['90 3c 64 3e 64 80 3c 00', 'b0 07 7f 07 00 e0 00 40', 'f0 7e 7f 09 01 f7 c0 05',
          '90 3c f8 64 fe', 'f2 10 20 f3 01 f6 b0 40 7f']:
    add('fuzz_midi', hexbytes(s))
for s in ['09 90 3c 64 08 80 3c 00', '0b b0 07 7f 1b b1 10 20', '04 f0 7e 7f 07 09 01 f7', '0f f8 00 00 05 f6 00 00']:
    add('fuzz_usb_midi', hexbytes(s))
v = corpus_json('midi/parser-vectors/midi1_stream_vectors.json')
for t in (v or {}).get('vectors', []):
    add('fuzz_midi', hexbytes(t['input_hex']))
v = corpus_json('midi/parser-vectors/usb_midi_packet_vectors.json')
packets = [hexbytes(t['packet_hex']) for t in (v or {}).get('decode', []) if 'packet_hex' in t]
for i in range(0, len(packets), 4):
    add('fuzz_usb_midi', b''.join(packets[i:i + 4]))

# HID: a report descriptor with reports. Ours: a joystick (X and Y 8-bit, 8 buttons) and the
# same with a report ID; then the corpus's descriptors.
joystick = ('05 01 09 04 a1 01 {id} 09 30 09 31 15 00 26 ff 00 75 08 95 02 81 02 '
            '05 09 19 01 29 08 15 00 25 01 75 01 95 08 81 02 c0')
hid_descriptors = [hexbytes(joystick.format(id='')), hexbytes(joystick.format(id='85 01'))]
hid_descriptors += [hexbytes(open(p).read())[:65535] for p in sorted(glob.glob(f'{corpus}/hid/*descriptors/*.hex'))[:40]]
for d in hid_descriptors:
    reports = b''.join(bytes([n]) + bytes((k * 37 + n) & 0xFF for k in range(n)) for n in (3, 8, 16, 64))
    add('fuzz_hid', struct.pack('<H', len(d)) + d + reports)

# OSC: a pattern, NUL, a message (address, type tags, one float).
def osc_string(s):
    b = s.encode() + b'\0'
    return b + b'\0' * (-len(b) % 4)
for pat, addr in [('/fader/*', '/fader/1'), ('/{a,b}/[0-9]', '/a/3'), ('/xy/?', '/xy/1'), ('/*/*', '/pad/x')]:
    add('fuzz_osc', pat.encode() + b'\0' + osc_string(addr) + osc_string(',f') + struct.pack('>f', 0.5))

# PNG images (small ones: the harness refuses inputs over 64 KB).
for p in sorted(glob.glob(f'{src}/config/characters/*.png') + glob.glob(f'{corpus}/raster/**/*.png', recursive=True)):
    if os.path.getsize(p) <= 65536:
        add('fuzz_raster', read(p))

# Recordings made by the caller (run.sh records a few simulated shows when it can).
for p in sorted(glob.glob(f'{out}/../recordings/*.marrec')):
    add('fuzz_recording', read(p))

for name, items in seeds.items():
    d = os.path.join(out, name)
    os.makedirs(d, exist_ok=True)
    for i, data in enumerate(items):
        with open(os.path.join(d, f'seed{i:04d}'), 'wb') as f:
            f.write(data)
print(' '.join(f'{n}:{len(i)}' for n, i in sorted(seeds.items())))
