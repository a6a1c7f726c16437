# expect: 3: values must increase: 5 is not above the value on line 2
10 1 1 1 0
5 1 1 1 1
