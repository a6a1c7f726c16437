# expect: 3: value is not a finite number: .nan.
0 0 0 0 0
nan 1 1 1 1
