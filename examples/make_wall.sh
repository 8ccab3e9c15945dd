#!/bin/sh
# Write a running-bond brick wall as a cairn assembly: make_wall.sh ROWS COLS FRICTION > wall.json
# Bricks are 2 x 1; odd rows are shifted by half a brick; the ground is fixed.
rows=${1:-10}; cols=${2:-20}; mu=${3:-0.6}
awk -v rows="$rows" -v cols="$cols" -v mu="$mu" 'BEGIN {
  printf "{\n  \"name\": \"Running-bond wall of %d bricks (%d rows of %d), friction %s\",\n", rows*cols, rows, cols, mu
  printf "  \"dimension\": 2,\n  \"friction\": %s,\n  \"parts\": [\n", mu
  printf "    {\"name\": \"ground\", \"fixed\": true, \"polygon\": [[-2,-1],[%d,-1],[%d,0],[-2,0]]}", 2*cols+3, 2*cols+3
  for (r = 0; r < rows; r++) for (c = 0; c < cols; c++) {
    x = 2*c + (r % 2)
    printf ",\n    {\"name\": \"r%dc%d\", \"polygon\": [[%d,%d],[%d,%d],[%d,%d],[%d,%d]]}", r, c, x, r, x+2, r, x+2, r+1, x, r+1
  }
  printf "\n  ]\n}\n"
}'
