# expect: 2: alpha must lie in \[0, 1\], got 1.5
0 1 1 1 1.5
