# expect: 2: g must lie in \[0, 1\], got -0.1
0 1 -0.1 1 0.5
