//! Block loops, on rayon or on the calling thread.
//!
//! Most per-iteration work is a loop over the cone blocks. On problems with little work per
//! iteration (a few small blocks, `m` of tens) a task hand-off costs more than a block, and even
//! a one-thread pool costs a thread start, a fresh allocator arena and a cross-thread hand-off
//! per solve (truss1: ~40% of the in-process time). Such problems run every loop as a plain
//! loop on the caller's thread ([`Exec::Sequential`]); the others run on rayon
//! ([`Exec::Parallel`]). Every loop writes each result slot from exactly one iteration, so both
//! give bitwise identical results.
//!
//! The dense factorisations and solves of the whole system (Cholesky of the Schur matrix in
//! `linsys`, Householder QR in `lsq`) run on the calling thread (faer `Par::Seq`) whatever the
//! thread count. faer's parallel kernels split their work by the number of threads, so their
//! rounding — and with it the iterates — would depend on it (gpp250-1 took 17 iterations on two
//! threads, 19 on one); and they synchronise by spinning at barriers, which on a machine shared
//! with other work costs far more than it saves (gpp250-1: 23.6 s on two threads, 58% of the
//! samples spinning in faer's barrier, against 5.9 s on one).

use rayon::prelude::*;

/// How the block loops of one solve run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Exec {
    /// Plain loops on the calling thread; rayon is never entered.
    Sequential,
    /// Parallel loops on the current rayon pool.
    Parallel,
}

impl Exec {
    /// `(0..len).map(f).collect()`.
    pub(crate) fn map<T, F>(self, len: usize, f: F) -> Vec<T>
    where
        T: Send,
        F: Fn(usize) -> T + Sync + Send,
    {
        match self {
            Exec::Sequential => (0..len).map(f).collect(),
            Exec::Parallel => (0..len).into_par_iter().map(f).collect(),
        }
    }

    /// `f(k, &mut items[k])` for every `k`.
    pub(crate) fn for_each_mut<T, F>(self, items: &mut [T], f: F)
    where
        T: Send,
        F: Fn(usize, &mut T) + Sync + Send,
    {
        match self {
            Exec::Sequential => items.iter_mut().enumerate().for_each(|(k, t)| f(k, t)),
            Exec::Parallel => items.par_iter_mut().enumerate().for_each(|(k, t)| f(k, t)),
        }
    }

    /// `f(p, chunk)` for the consecutive chunks of `size` entries of `buf`, with one scratch
    /// value (from `init`) per task.
    pub(crate) fn chunks_mut<T, S, I, F>(self, buf: &mut [T], size: usize, init: I, f: F)
    where
        T: Send,
        I: Fn() -> S + Sync + Send,
        F: Fn(&mut S, usize, &mut [T]) + Sync + Send,
    {
        match self {
            Exec::Sequential => {
                let mut scratch = init();
                for (p, chunk) in buf.chunks_mut(size).enumerate() {
                    f(&mut scratch, p, chunk);
                }
            }
            Exec::Parallel => buf
                .par_chunks_mut(size)
                .enumerate()
                .for_each_init(init, |s, (p, chunk)| f(s, p, chunk)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Exec;

    #[test]
    fn both_modes_fill_every_slot_identically() {
        for exec in [Exec::Sequential, Exec::Parallel] {
            assert_eq!(exec.map(5, |k| k * k), vec![0, 1, 4, 9, 16]);
            let mut v = vec![1.0; 7];
            exec.for_each_mut(&mut v, |k, x| *x += k as f64);
            assert_eq!(v, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
            let mut buf = vec![0usize; 10];
            exec.chunks_mut(
                &mut buf,
                3,
                || 0usize,
                |calls, p, c| {
                    *calls += 1;
                    c.fill(10 * p + c.len());
                },
            );
            assert_eq!(buf, vec![3, 3, 3, 13, 13, 13, 23, 23, 23, 31]);
        }
    }
}
