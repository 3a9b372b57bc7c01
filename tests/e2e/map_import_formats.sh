# map-import on the real KITTI PLY (x y z intensity), and on a PCD with intensity written from it.
source "$(dirname "$0")/common.sh"
"$BIN/map-import" --input "$SHARED/data/kitti_raw_seq78/map_even_frames_5cm.ply" --output "$WORK/kitti.map" \
  | tee "$WORK/ply.txt"
[ -s "$WORK/kitti.map" ] || fail "map not written"
expect_contains "$WORK/ply.txt" "1061716"
# A small binary PCD with an intensity field, written by hand.
/usr/bin/python3 - "$WORK/small.pcd" <<'PY'
import struct, sys
pts = [(0.0, 0.0, 1.0, 10.0), (1.0, 2.0, 3.0, 200.0), (-1.5, 0.5, 2.0, 255.0), (4.0, -3.0, 0.25, 0.0)]
hdr = ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\n"
       "TYPE F F F F\nCOUNT 1 1 1 1\nWIDTH %d\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA binary\n" % (len(pts), len(pts)))
with open(sys.argv[1], "wb") as f:
    f.write(hdr.encode())
    for p in pts: f.write(struct.pack("<4f", *p))
PY
"$BIN/map-import" --input "$WORK/small.pcd" --output "$WORK/small.map" | tee "$WORK/pcd.txt"
[ -s "$WORK/small.map" ] || fail "PCD map not written"
expect_contains "$WORK/pcd.txt" "4 points"
echo "OK"
