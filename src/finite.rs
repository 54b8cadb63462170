//! Find the first non-finite number in anything serializable, by its JSON path: serde_json
//! writes NaN and infinities as `null`, which a reader cannot tell from a missing value.

use serde::ser::{self, Serialize};
use std::fmt::Display;

/// The JSON path (`samples[0].nodes[3].origin[1]`) of the first NaN or infinity in `v`.
pub fn first_nonfinite<T: Serialize + ?Sized>(v: &T) -> Option<String> {
    match v.serialize(Finder(String::new())) {
        Err(Found::At(p)) => Some(if p.is_empty() { "(top)".into() } else { p }),
        _ => None,
    }
}

#[derive(Debug)]
enum Found {
    At(String),
    Other,
}

impl Display for Found {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Found::At(p) => write!(f, "non-finite number at {p}"),
            Found::Other => f.write_str("not serializable"),
        }
    }
}

impl std::error::Error for Found {}

impl ser::Error for Found {
    fn custom<T: Display>(_: T) -> Self {
        Found::Other
    }
}

struct Finder(String);

/// A compound value: its path and the index of the next element.
struct Walk(String, usize);

impl Walk {
    fn elem<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
        let p = format!("{}[{}]", self.0, self.1);
        self.1 += 1;
        v.serialize(Finder(p))
    }
    fn field<T: Serialize + ?Sized>(&mut self, k: &str, v: &T) -> Result<(), Found> {
        let p = if self.0.is_empty() {
            k.to_string()
        } else {
            format!("{}.{k}", self.0)
        };
        v.serialize(Finder(p))
    }
}

macro_rules! ok {
    ($($f:ident: $t:ty),*) => { $(fn $f(self, _: $t) -> Result<(), Found> { Ok(()) })* };
}

impl ser::Serializer for Finder {
    type Ok = ();
    type Error = Found;
    type SerializeSeq = Walk;
    type SerializeTuple = Walk;
    type SerializeTupleStruct = Walk;
    type SerializeTupleVariant = Walk;
    type SerializeMap = Walk;
    type SerializeStruct = Walk;
    type SerializeStructVariant = Walk;
    ok!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
        serialize_i64: i64, serialize_u8: u8, serialize_u16: u16, serialize_u32: u32,
        serialize_u64: u64, serialize_char: char, serialize_str: &str,
        serialize_bytes: &[u8], serialize_unit_struct: &'static str);
    fn serialize_f32(self, v: f32) -> Result<(), Found> {
        self.serialize_f64(f64::from(v))
    }
    fn serialize_f64(self, v: f64) -> Result<(), Found> {
        if v.is_finite() {
            Ok(())
        } else {
            Err(Found::At(self.0))
        }
    }
    fn serialize_none(self) -> Result<(), Found> {
        Ok(())
    }
    fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<(), Found> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), Found> {
        Ok(())
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> Result<(), Found> {
        Ok(())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<(), Found> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        v: &T,
    ) -> Result<(), Found> {
        Walk(self.0, 0).field(variant, v)
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Walk, Found> {
        Ok(Walk(self.0, 0))
    }
    fn serialize_tuple(self, _: usize) -> Result<Walk, Found> {
        Ok(Walk(self.0, 0))
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Walk, Found> {
        Ok(Walk(self.0, 0))
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        v: &'static str,
        _: usize,
    ) -> Result<Walk, Found> {
        Ok(Walk(format!("{}.{v}", self.0), 0))
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Walk, Found> {
        Ok(Walk(self.0, 0))
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Walk, Found> {
        Ok(Walk(self.0, 0))
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        v: &'static str,
        _: usize,
    ) -> Result<Walk, Found> {
        Ok(Walk(format!("{}.{v}", self.0), 0))
    }
}

macro_rules! seqlike {
    ($($tr:ident :: $m:ident),*) => {$(
        impl ser::$tr for Walk {
            type Ok = ();
            type Error = Found;
            fn $m<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
                self.elem(v)
            }
            fn end(self) -> Result<(), Found> {
                Ok(())
            }
        }
    )*};
}
seqlike!(
    SerializeSeq::serialize_element,
    SerializeTuple::serialize_element,
    SerializeTupleStruct::serialize_field,
    SerializeTupleVariant::serialize_field
);

macro_rules! structlike {
    ($($tr:ident),*) => {$(
        impl ser::$tr for Walk {
            type Ok = ();
            type Error = Found;
            fn serialize_field<T: Serialize + ?Sized>(&mut self, k: &'static str, v: &T) -> Result<(), Found> {
                self.field(k, v)
            }
            fn end(self) -> Result<(), Found> {
                Ok(())
            }
        }
    )*};
}
structlike!(SerializeStruct, SerializeStructVariant);

impl ser::SerializeMap for Walk {
    type Ok = ();
    type Error = Found;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, k: &T) -> Result<(), Found> {
        k.serialize(Finder(format!("{}<key>", self.0)))
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
        self.elem(v)
    }
    fn end(self) -> Result<(), Found> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::first_nonfinite;

    #[derive(serde::Serialize)]
    struct Node {
        parent: Option<u32>,
        origin: [f64; 3],
        cos_t: Option<f64>,
    }

    #[test]
    fn finds_the_path_of_a_nan_and_not_a_none() {
        let ok = Node {
            parent: None,
            origin: [1.0, 2.0, 3.0],
            cos_t: None,
        };
        assert_eq!(first_nonfinite(&vec![ok]), None);
        let bad = Node {
            parent: Some(1),
            origin: [1.0, f64::NAN, 3.0],
            cos_t: None,
        };
        assert_eq!(
            first_nonfinite(&vec![bad]).as_deref(),
            Some("[0].origin[1]")
        );
        let inf = Node {
            parent: None,
            origin: [0.0; 3],
            cos_t: Some(f64::INFINITY),
        };
        assert_eq!(first_nonfinite(&inf).as_deref(), Some("cos_t"));
        assert_eq!(
            first_nonfinite(&glam::DVec3::new(0.0, f64::NEG_INFINITY, 0.0)).as_deref(),
            Some("[1]")
        );
    }
}
