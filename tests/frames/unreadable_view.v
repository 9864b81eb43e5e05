scale: 2
bad 12abc
#garbage here
