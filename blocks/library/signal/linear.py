"""Linear-system kernels shared by the dynamic signal blocks (numba-compiled, callable from Python too)."""

from numba import njit

UNLIMITED = 1e300
"""Default output limit of the limited blocks: finite (parameters must be), far beyond any signal."""


@njit(cache=True)
def clamp(x, lower, upper):
    """min(max(x, lower), upper)."""
    return min(max(x, lower), upper)


@njit(cache=True)
def tf_numerator(num, den, k):
    """Coefficient b_k (k = 0..n) of s^(n-k) of the numerator padded to the denominator's length n+1 and
    normalised by den[0]. Leading entries of ``num`` beyond that length are ignored (they must be zero)."""
    n = den.shape[0] - 1
    idx = k - (n + 1 - num.shape[0])
    if idx < 0:
        return 0.0
    return num[idx] / den[0]


@njit(cache=True)
def tf_state_output(x, num, den):
    """C x of the controllable canonical form: sum_k (b_k - a_k*b_0) x[k-1], a_k = den[k]/den[0]."""
    n = den.shape[0] - 1
    b0 = tf_numerator(num, den, 0)
    y = 0.0
    for k in range(1, n + 1):
        y += (tf_numerator(num, den, k) - den[k] / den[0] * b0) * x[k - 1]
    return y


@njit(cache=True)
def tf_derivatives(u, x, den, der_x):
    """Fill der_x = A x + B u of the controllable canonical form (scipy.signal.tf2ss's realisation):
    der_x[0] = u - sum_k a_k x[k-1], der_x[k] = x[k-1] for k >= 1."""
    n = den.shape[0] - 1
    if n == 0:
        return
    acc = u
    for k in range(1, n + 1):
        acc -= den[k] / den[0] * x[k - 1]
    for k in range(n - 1, 0, -1):
        der_x[k] = x[k - 1]
    der_x[0] = acc


@njit(cache=True)
def lowpass2_acceleration(u, x, dx, wn, zeta):
    """d2x/dt2 of x'' + 2*zeta*wn*x' + wn^2*x = wn^2*u (unit static gain: x is u low-pass filtered)."""
    return wn * (wn * (u - x) - 2.0 * zeta * dx)


# ---- build-time check (plain Python; called through the transfer-function blocks' ``check_values``) ----
def check_transfer_function(num, den, strict: bool) -> str | None:
    """None if num/den is proper (strictly proper if ``strict``) with den[0] != 0, else what is wrong."""
    num = [float(v) for v in num]
    den = [float(v) for v in den]
    if not num or not den:
        return "num and den must be non-empty"
    if den[0] == 0.0:
        return "den[0] (the leading denominator coefficient) must not be zero"
    lead = 0
    while lead < len(num) - 1 and num[lead] == 0.0:
        lead += 1
    deg_num, deg_den = len(num) - 1 - lead, len(den) - 1
    if any(v != 0.0 for v in num) and deg_num > deg_den:
        return f"improper transfer function: deg num = {deg_num} > deg den = {deg_den}"
    if strict and any(v != 0.0 for v in num) and deg_num == deg_den:
        return (f"deg num = deg den = {deg_den}: not strictly proper; use transfer_function "
                "(it has direct feedthrough)")
    return None
