//! A job's result as text that reads back bit for bit: MessagePack (fields by name, every `f64`
//! as its 8 bytes, NaN and infinities included) written as lowercase hexadecimal. JSON numbers
//! cannot hold a NaN nor an infinity, which the stability suite's records carry.

use serde::de::DeserializeOwned;
use serde::Serialize;

use super::ShardError;

/// `result` as hexadecimal MessagePack.
pub fn encode<T: Serialize>(result: &T) -> Result<String, ShardError> {
    let bytes = rmp_serde::to_vec_named(result).map_err(|e| ShardError::Encode(e.to_string()))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// The result that [`encode`] wrote as `text`, the job at `index` of its list.
pub fn decode<T: DeserializeOwned>(index: usize, text: &str) -> Result<T, ShardError> {
    read(text).map_err(|why| ShardError::Decode { index, why })
}

/// The value that [`encode`] wrote as `text` (a job's result, or a shard's recorded request),
/// or why it does not read.
pub fn read<T: DeserializeOwned>(text: &str) -> Result<T, String> {
    if text.len() % 2 != 0 {
        return Err("an odd number of hexadecimal digits".into());
    }
    let bytes = (0..text.len())
        .step_by(2)
        .map(|i| {
            text.get(i..i + 2)
                .and_then(|pair| u8::from_str_radix(pair, 16).ok())
                .ok_or_else(|| format!("not hexadecimal at character {i}"))
        })
        .collect::<Result<Vec<u8>, _>>()?;
    rmp_serde::from_slice(&bytes).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_f64_reads_back_bit_for_bit() {
        let values = vec![
            0.1,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE / 3.0,
            1.0 / 3.0,
            f64::from_bits(0x000f_ffff_ffff_ffff),
        ];
        let back: Vec<f64> = decode(0, &encode(&values).unwrap()).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&values));
    }

    #[test]
    fn damaged_text_is_an_error_naming_the_job() {
        let e = decode::<f64>(7, "zz").unwrap_err().to_string();
        assert!(e.contains("job 7"), "{e}");
        assert!(decode::<f64>(7, "abc").is_err());
    }
}
