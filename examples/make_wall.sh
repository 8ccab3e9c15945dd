#!/bin/sh
# Write a running-bond brick wall as a cairn assembly: make_wall.sh ROWS COLS FRICTION [flush] > wall.json
# Bricks are 2 x 1; odd rows are shifted by half a brick, so their end bricks sit with their centre
# over the edge of the brick below; with "flush", odd rows start and end with a half brick (1 x 1)
# instead, the wall's ends straight. The ground is fixed.
rows=${1:-10}; cols=${2:-20}; mu=${3:-0.6}; flush=${4:-}
awk -v rows="$rows" -v cols="$cols" -v mu="$mu" -v flush="$flush" 'BEGIN {
  n = 0
  for (r = 0; r < rows; r++) n += (flush == "flush" && r % 2) ? cols + 1 : cols
  printf "{\n  \"name\": \"Running-bond wall of %d bricks (%d rows of %d%s), friction %s\",\n", n, rows, cols, flush == "flush" ? ", flush ends" : "", mu
  printf "  \"dimension\": 2,\n  \"friction\": %s,\n  \"parts\": [\n", mu
  printf "    {\"name\": \"ground\", \"fixed\": true, \"polygon\": [[-2,-1],[%d,-1],[%d,0],[-2,0]]}", 2*cols+3, 2*cols+3
  for (r = 0; r < rows; r++) {
    if (flush == "flush" && r % 2) {
      for (c = 0; c <= cols; c++) {
        x0 = c == 0 ? 0 : 2*c - 1; x1 = c == cols ? 2*cols : 2*c + 1
        printf ",\n    {\"name\": \"r%dc%d\", \"polygon\": [[%d,%d],[%d,%d],[%d,%d],[%d,%d]]}", r, c, x0, r, x1, r, x1, r+1, x0, r+1
      }
      continue
    }
    for (c = 0; c < cols; c++) {
      x = 2*c + (flush == "flush" ? 0 : r % 2)
      printf ",\n    {\"name\": \"r%dc%d\", \"polygon\": [[%d,%d],[%d,%d],[%d,%d],[%d,%d]]}", r, c, x, r, x+2, r, x+2, r+1, x, r+1
    }
  }
  printf "\n  ]\n}\n"
}'
