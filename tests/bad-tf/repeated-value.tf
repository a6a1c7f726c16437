# expect: 3: values must increase: 10 is not above the value on line 2
10 1 1 1 0
10 1 1 1 1
