#ifndef CPP_INCLUDE_HELPER_H
#define CPP_INCLUDE_HELPER_H
const int BASE = 7;
inline int combine(int a, int b) { return a * BASE + b; }
#define HELPER_STEPS 2
#endif
