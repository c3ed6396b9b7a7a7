//! A stable insertion sort for the kernel's short fixed-capacity lists (the volume solver's roots, the zone
//! order, the children on the traversal stack): no allocation, no panic path.

/// Sorts a short slice stably in place so that no element is preceded by one it goes `before` (incomparable
/// elements such as NaNs stay where they are).
#[inline]
pub(crate) fn insertion_sort<E>(v: &mut [E], before: impl Fn(&E, &E) -> bool) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 {
            let jm = j.saturating_sub(1);
            let (Some(x), Some(y)) = (v.get(jm), v.get(j)) else {
                break;
            };
            if before(y, x) {
                v.swap(jm, j);
                j = jm;
            } else {
                break;
            }
        }
    }
}
