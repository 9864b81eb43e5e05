rule Stem(a) 
rule F(l,d) 
