//! A content hash for generated-file headers: FNV-1a, 64 bits. Not cryptographic; it only has
//! to change when a description changes, identically on every machine.

pub fn fnv1a64(chunks: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for chunk in chunks {
        for &b in *chunk {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        // Separate files so that moving bytes between them changes the hash.
        h ^= 0xff;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::fnv1a64;

    #[test]
    fn matches_the_published_fnv1a_test_vector_for_one_chunk() {
        // FNV-1a 64 of "a" is 0xaf63dc4c8601ec8c; our separator then mixes in 0xff.
        let expected = (0xaf63dc4c8601ec8c_u64 ^ 0xff).wrapping_mul(0x0000_0100_0000_01b3);
        assert_eq!(fnv1a64(&[b"a"]), expected);
        assert_ne!(fnv1a64(&[b"ab", b"c"]), fnv1a64(&[b"a", b"bc"]));
    }
}
