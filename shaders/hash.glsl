// A 32-bit integer hash (lowbias32: two multiply-xorshift rounds), for per-pixel and
// per-point random numbers in the shaders.
uint hash_uint(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
