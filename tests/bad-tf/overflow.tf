# expect: 2: value is not a finite number: .1e999.
1e999 0 0 0 0
