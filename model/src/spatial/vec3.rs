//! 3-vectors and 3×3 matrices over a [`Scalar`].

use crate::scalar::Scalar;
use std::ops::{Add, Mul, Neg, Sub};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vec3<S>(pub [S; 3]);

/// Row-major 3×3 matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mat3<S>(pub [[S; 3]; 3]);

impl<S: Copy> Vec3<S> {
    /// `f` entry by entry (a vector over another scalar type).
    pub fn map<T>(&self, f: impl Fn(S) -> T) -> Vec3<T> {
        Vec3(self.0.map(f))
    }
}

impl<S: Copy> Mat3<S> {
    /// `f` entry by entry.
    pub fn map<T>(&self, f: impl Fn(S) -> T) -> Mat3<T> {
        Mat3(self.0.map(|row| row.map(&f)))
    }
}

impl<S: Scalar> Vec3<S> {
    pub fn zero() -> Self {
        Vec3([S::zero(); 3])
    }
    pub fn from_f64(v: [f64; 3]) -> Self {
        Vec3(v.map(S::from_f64))
    }
    pub fn dot(&self, o: &Self) -> S {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }
    pub fn cross(&self, o: &Self) -> Self {
        let [a, b, c] = self.0;
        let [x, y, z] = o.0;
        Vec3([b * z - c * y, c * x - a * z, a * y - b * x])
    }
    pub fn scale(&self, k: S) -> Self {
        Vec3(self.0.map(|x| x * k))
    }
}

impl<S: Scalar> Add for Vec3<S> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Vec3([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}
impl<S: Scalar> Sub for Vec3<S> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Vec3([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }
}
impl<S: Scalar> Neg for Vec3<S> {
    type Output = Self;
    fn neg(self) -> Self {
        Vec3(self.0.map(|x| -x))
    }
}

impl<S: Scalar> Mat3<S> {
    pub fn identity() -> Self {
        let (o, z) = (S::one(), S::zero());
        Mat3([[o, z, z], [z, o, z], [z, z, o]])
    }
    pub fn from_f64(m: [[f64; 3]; 3]) -> Self {
        Mat3(m.map(|r| r.map(S::from_f64)))
    }
    pub fn transpose(&self) -> Self {
        let m = &self.0;
        Mat3([
            [m[0][0], m[1][0], m[2][0]],
            [m[0][1], m[1][1], m[2][1]],
            [m[0][2], m[1][2], m[2][2]],
        ])
    }
    /// `self · v`.
    pub fn mul_vec(&self, v: &Vec3<S>) -> Vec3<S> {
        Vec3(self.0.map(|r| r[0] * v.0[0] + r[1] * v.0[1] + r[2] * v.0[2]))
    }
    /// `selfᵀ · v`.
    pub fn tr_mul_vec(&self, v: &Vec3<S>) -> Vec3<S> {
        let m = &self.0;
        Vec3(std::array::from_fn(|j| {
            m[0][j] * v.0[0] + m[1][j] * v.0[1] + m[2][j] * v.0[2]
        }))
    }
    pub fn column(&self, j: usize) -> Vec3<S> {
        Vec3([self.0[0][j], self.0[1][j], self.0[2][j]])
    }
}

impl<S: Scalar> Mul for Mat3<S> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let (a, b) = (&self.0, &o.0);
        Mat3(std::array::from_fn(|i| {
            std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
        }))
    }
}
