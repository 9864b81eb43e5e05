// A view file with mistakes: lcjit warns with file:line:column and applies the rest.
line style: cylinder
this is not a command
contour sides: many
scale: 0.5
