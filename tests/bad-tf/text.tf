# expect: 2: r is not a finite number: .red.
0 red 0 0 0
