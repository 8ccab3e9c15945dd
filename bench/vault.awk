# A semicircular arch (dimension 2) or barrel vault (3: voussoirs x courses, each course one
# unit deep) of radius 10 and thickness 1.5 on a ground block, as a cairn assembly file.
#   awk -v dim=3 -v n=VOUSSOIRS -v c=COURSES -v mu=FRICTION -f vault.awk
# (bench/run.sh's scale table and tests/blas_kernel.sh)
BEGIN { R = 10; t = 1.5; pi = atan2(0, -1)
    for (i = 0; i <= n; i++) { a = pi * i / n; ci[i] = R * cos(a); si[i] = R * sin(a)
      co[i] = (R + t) * cos(a); so[i] = (R + t) * sin(a) }
    si[n] = so[n] = 0; si[0] = so[0] = 0
    printf "{\"name\": \"%d-D vault of %d voussoirs\", \"dimension\": %d, \"friction\": %s, \"parts\": [\n", dim, n * c, dim, mu
    if (dim == 2) printf "{\"name\": \"ground\", \"fixed\": true, \"polygon\": [[-13, -1], [13, -1], [13, 0], [-13, 0]]}"
    else printf "{\"name\": \"ground\", \"fixed\": true, \"box\": {\"min\": [-13, -1, -1], \"max\": [13, %d, 0]}}", c + 1
    for (k = 0; k < c; k++) for (i = 0; i < n; i++) {
      if (dim == 2) printf ",\n{\"name\": \"v%d\", \"polygon\": [[%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g]]}", i, ci[i], si[i], co[i], so[i], co[i+1], so[i+1], ci[i+1], si[i+1]
      else {
        printf ",\n{\"name\": \"c%dv%d\", \"hull\": [", k, i
        for (y = k; y <= k + 1; y++) printf "%s[%.17g, %d, %.17g], [%.17g, %d, %.17g], [%.17g, %d, %.17g], [%.17g, %d, %.17g]", (y > k ? ", " : ""), ci[i], y, si[i], co[i], y, so[i], co[i+1], y, so[i+1], ci[i+1], y, si[i+1]
        printf "]}"
      }
    }
    printf "\n]}\n" }
