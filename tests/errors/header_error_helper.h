// Included by header_error.l.
inline float helper(float a) {
  return a + not_declared_here;
}
