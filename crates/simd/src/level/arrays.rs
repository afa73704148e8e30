//! The portable level off x86-64: arrays and a loop per operation, with x86's
//! definitions of the edge cases (see the module docs).
use super::{Avx2, Level, Portable, BIT_LANES};

macro_rules! lanes {
    (|$($a:ident),*| $e:expr) => {{
        let mut r = [Default::default(); 8];
        for i in 0..8 {
            $(let $a = $a[i];)*
            r[i] = $e;
        }
        r
    }};
}

fn floor1(x: f32) -> f32 {
    x.floor()
}

impl Level for Portable {
    type F = [f32; 8];
    type I = [i32; 8];
    const F_ZERO: [f32; 8] = [0.0; 8];
    const F_ONE: [f32; 8] = [1.0; 8];
    const F_RAMP: [f32; 8] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
    const I_ZERO: [i32; 8] = [0; 8];
    fn splat(x: f32) -> [f32; 8] {
        [x; 8]
    }
    fn from_array(a: [f32; 8]) -> [f32; 8] {
        a
    }
    fn to_array(a: [f32; 8]) -> [f32; 8] {
        a
    }
    fn add(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        lanes!(|a, b| a + b)
    }
    fn sub(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        lanes!(|a, b| a - b)
    }
    fn mul(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        lanes!(|a, b| a * b)
    }
    fn div(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        lanes!(|a, b| a / b)
    }
    fn fmax(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        lanes!(|a, b| if a > b { a } else { b })
    }
    fn fmin(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        lanes!(|a, b| if a < b { a } else { b })
    }
    fn sqrt(a: [f32; 8]) -> [f32; 8] {
        lanes!(|a| a.sqrt())
    }
    fn floor(a: [f32; 8]) -> [f32; 8] {
        lanes!(|a| floor1(a))
    }
    fn lt(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
        lanes!(|a, b| -i32::from(a < b))
    }
    fn le(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
        lanes!(|a, b| -i32::from(a <= b))
    }
    fn eq(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
        lanes!(|a, b| -i32::from(a == b))
    }
    fn select(m: [i32; 8], a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        lanes!(|m, a, b| if m < 0 { a } else { b })
    }
    fn bits(a: [f32; 8]) -> [i32; 8] {
        lanes!(|a| a.to_bits() as i32)
    }
    fn from_bits(a: [i32; 8]) -> [f32; 8] {
        lanes!(|a| f32::from_bits(a as u32))
    }
    fn to_int(a: [f32; 8]) -> [i32; 8] {
        lanes!(|a| if a > -2147483904.0 && a < 2147483648.0 {
            a as i32
        } else {
            i32::MIN
        })
    }
    fn to_float(a: [i32; 8]) -> [f32; 8] {
        lanes!(|a| a as f32)
    }
    fn isplat(x: i32) -> [i32; 8] {
        [x; 8]
    }
    fn ifrom_array(a: [i32; 8]) -> [i32; 8] {
        a
    }
    fn ito_array(a: [i32; 8]) -> [i32; 8] {
        a
    }
    fn iadd(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| a.wrapping_add(b))
    }
    fn isub(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| a.wrapping_sub(b))
    }
    fn imul(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| a.wrapping_mul(b))
    }
    fn and(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| a & b)
    }
    fn or(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| a | b)
    }
    fn xor(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| a ^ b)
    }
    fn andnot(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| !a & b)
    }
    fn shl<const N: i32>(a: [i32; 8]) -> [i32; 8] {
        lanes!(|a| a << N)
    }
    fn sra<const N: i32>(a: [i32; 8]) -> [i32; 8] {
        lanes!(|a| a >> N)
    }
    fn srl<const N: i32>(a: [i32; 8]) -> [i32; 8] {
        lanes!(|a| ((a as u32) >> N) as i32)
    }
    fn ieq(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| -i32::from(a == b))
    }
    fn igt(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|a, b| -i32::from(a > b))
    }
    fn iselect(m: [i32; 8], a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        lanes!(|m, a, b| if m < 0 { a } else { b })
    }
    fn movemask(a: [i32; 8]) -> u32 {
        let mut b = 0;
        for (i, v) in a.iter().enumerate() {
            b |= u32::from(*v < 0) << i;
        }
        b
    }
    fn mask_of(bits: u32) -> [i32; 8] {
        lanes!(|BIT_LANES| -i32::from(bits as i32 & BIT_LANES != 0))
    }
}

/// Off x86-64 the AVX2 level is never instantiated (no kernel uses it); it repeats the
/// portable one so generic code compiles.
impl Level for Avx2 {
    type F = [f32; 8];
    type I = [i32; 8];
    const F_ZERO: [f32; 8] = Portable::F_ZERO;
    const F_ONE: [f32; 8] = Portable::F_ONE;
    const F_RAMP: [f32; 8] = Portable::F_RAMP;
    const I_ZERO: [i32; 8] = Portable::I_ZERO;
    fn splat(x: f32) -> [f32; 8] {
        Portable::splat(x)
    }
    fn from_array(a: [f32; 8]) -> [f32; 8] {
        a
    }
    fn to_array(a: [f32; 8]) -> [f32; 8] {
        a
    }
    fn add(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        Portable::add(a, b)
    }
    fn sub(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        Portable::sub(a, b)
    }
    fn mul(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        Portable::mul(a, b)
    }
    fn div(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        Portable::div(a, b)
    }
    fn fmax(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        Portable::fmax(a, b)
    }
    fn fmin(a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        Portable::fmin(a, b)
    }
    fn sqrt(a: [f32; 8]) -> [f32; 8] {
        Portable::sqrt(a)
    }
    fn floor(a: [f32; 8]) -> [f32; 8] {
        Portable::floor(a)
    }
    fn lt(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
        Portable::lt(a, b)
    }
    fn le(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
        Portable::le(a, b)
    }
    fn eq(a: [f32; 8], b: [f32; 8]) -> [i32; 8] {
        Portable::eq(a, b)
    }
    fn select(m: [i32; 8], a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        Portable::select(m, a, b)
    }
    fn bits(a: [f32; 8]) -> [i32; 8] {
        Portable::bits(a)
    }
    fn from_bits(a: [i32; 8]) -> [f32; 8] {
        Portable::from_bits(a)
    }
    fn to_int(a: [f32; 8]) -> [i32; 8] {
        Portable::to_int(a)
    }
    fn to_float(a: [i32; 8]) -> [f32; 8] {
        Portable::to_float(a)
    }
    fn isplat(x: i32) -> [i32; 8] {
        [x; 8]
    }
    fn ifrom_array(a: [i32; 8]) -> [i32; 8] {
        a
    }
    fn ito_array(a: [i32; 8]) -> [i32; 8] {
        a
    }
    fn iadd(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::iadd(a, b)
    }
    fn isub(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::isub(a, b)
    }
    fn imul(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::imul(a, b)
    }
    fn and(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::and(a, b)
    }
    fn or(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::or(a, b)
    }
    fn xor(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::xor(a, b)
    }
    fn andnot(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::andnot(a, b)
    }
    fn shl<const N: i32>(a: [i32; 8]) -> [i32; 8] {
        Portable::shl::<N>(a)
    }
    fn sra<const N: i32>(a: [i32; 8]) -> [i32; 8] {
        Portable::sra::<N>(a)
    }
    fn srl<const N: i32>(a: [i32; 8]) -> [i32; 8] {
        Portable::srl::<N>(a)
    }
    fn ieq(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::ieq(a, b)
    }
    fn igt(a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::igt(a, b)
    }
    fn iselect(m: [i32; 8], a: [i32; 8], b: [i32; 8]) -> [i32; 8] {
        Portable::iselect(m, a, b)
    }
    fn movemask(a: [i32; 8]) -> u32 {
        Portable::movemask(a)
    }
    fn mask_of(bits: u32) -> [i32; 8] {
        Portable::mask_of(bits)
    }
}
