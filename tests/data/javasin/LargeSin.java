import java.util.SplittableRandom;
// Golden values of Java's Math.sin above 90112 (HotSpot's large-argument path):
// java LargeSin > large_sin.tsv; then gzip. Deterministic draws (SplittableRandom(36)).
public class LargeSin {
  static void out(StringBuilder sb, String set, double x) {
    sb.append(set).append('\t').append(String.format("%016x", Double.doubleToRawLongBits(x))).append('\t')
      .append(String.format("%016x", Double.doubleToRawLongBits(Math.sin(x)))).append('\n');
  }
  public static void main(String[] a) {
    SplittableRandom r = new SplittableRandom(36);
    StringBuilder sb = new StringBuilder();
    // log-uniform magnitudes from 90112 to Double.MAX_VALUE, both signs
    for (int i = 0; i < 30000; ++i) {
      double e = 16.46 + r.nextDouble() * (1023.99 - 16.46);
      double x = Math.pow(2, e);
      if (Double.isInfinite(x)) continue;
      out(sb, "large", r.nextBoolean() ? x : -x);
    }
    // every exponent, random mantissas
    for (int e = 16; e <= 1023; ++e) for (int k = 0; k < 8; ++k) {
      long bits = ((long)(e + 1023) << 52) | (r.nextLong() & 0xfffffffffffffL);
      double x = Double.longBitsToDouble(bits);
      if (Math.abs(x) >= 90112) out(sb, "exponent", r.nextBoolean() ? x : -x);
    }
    // near multiples of pi/4 (worst reductions): n*pi/4 rounded and neighbours
    for (int i = 0; i < 4000; ++i) {
      double n = Math.floor(Math.pow(2, 17 + r.nextDouble() * 45));
      double x = n * (Math.PI / 4);
      for (int d = -2; d <= 2; ++d) { double y = x; for (int j = 0; j < Math.abs(d); ++j) y = d > 0 ? Math.nextUp(y) : Math.nextDown(y); if (Math.abs(y) >= 90112) out(sb, "quarterpi", y); }
    }
    double[] edges = {90112, Math.nextUp(90112.0), 1e5, 1e6, 1e22, 1e300, Double.MAX_VALUE, 0x1p1023, 0x1p52, 0x1p53, 0x1p63, 0x1p64, 6.7e7, 105414336, 3.0e9};
    for (double x : edges) { out(sb, "edge", x); out(sb, "edge", -x); }
    System.out.print(sb);
  }
}
