//! A material as JSON: `{"model": ..., <parameters>, <compressibility>}`, the
//! compressibility being at most one of `bulk_ratio`, `d` and
//! `incompressible`. None stated means what ABAQUS/Explicit does with D = 0,
//! the authors' setting: K₀/μ₀ = 20 ([`Compressibility::abaqus_explicit`]).
//! Written back, the compressibility is always stated.

use serde::{Deserialize, Serialize};

use super::{Compressibility, Law, Material};

/// The three ways to state compressibility, as they appear in JSON.
struct Stated {
    bulk_ratio: Option<f64>,
    d: Option<f64>,
    incompressible: Option<bool>,
}

/// The JSON form: every model's parameters plus the compressibility fields
/// (written out per variant so that unknown fields stay errors).
macro_rules! material_json {
    ($($variant:ident { $($field:ident : $ty:ty),* }),* $(,)?) => {
        #[derive(Serialize, Deserialize)]
        #[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
        enum MaterialJson {
            $($variant {
                $($field: $ty,)*
                #[serde(default, skip_serializing_if = "Option::is_none")]
                bulk_ratio: Option<f64>,
                #[serde(default, skip_serializing_if = "Option::is_none")]
                d: Option<f64>,
                #[serde(default, skip_serializing_if = "Option::is_none")]
                incompressible: Option<bool>,
            },)*
        }

        impl MaterialJson {
            fn split(self) -> (Law, Stated) {
                match self {
                    $(MaterialJson::$variant { $($field,)* bulk_ratio, d, incompressible } => (
                        Law::$variant { $($field),* },
                        Stated { bulk_ratio, d, incompressible },
                    ),)*
                }
            }

            fn join(law: Law, stated: Stated) -> MaterialJson {
                let Stated { bulk_ratio, d, incompressible } = stated;
                match law {
                    $(Law::$variant { $($field),* } => MaterialJson::$variant {
                        $($field,)* bulk_ratio, d, incompressible,
                    },)*
                }
            }
        }
    };
}

material_json! {
    NeoHookean { mu_mpa: f64 },
    MooneyRivlin { c10_mpa: f64, c01_mpa: f64 },
    Gent { mu_mpa: f64, jm: f64 },
    ArrudaBoyce { mu_mpa: f64, lambda_m: f64 },
    Ogden { mu_mpa: Vec<f64>, alpha: Vec<f64> },
}

impl TryFrom<MaterialJson> for Material {
    type Error = String;

    fn try_from(json: MaterialJson) -> Result<Material, String> {
        let (model, stated) = json.split();
        let compressibility = match stated {
            Stated {
                bulk_ratio: Some(r),
                d: None,
                incompressible: None,
            } => Compressibility::BulkRatio(r),
            Stated {
                bulk_ratio: None,
                d: Some(d),
                incompressible: None,
            } => Compressibility::D(d),
            Stated {
                bulk_ratio: None,
                d: None,
                incompressible: Some(true),
            } => Compressibility::Incompressible,
            Stated {
                bulk_ratio: None,
                d: None,
                incompressible: None,
            } => Compressibility::abaqus_explicit(),
            Stated {
                bulk_ratio: None,
                d: None,
                incompressible: Some(false),
            } => {
                return Err(
                    "incompressible: false is not a compressibility; give bulk_ratio \
                            (K₀/μ₀) or d instead"
                        .into(),
                );
            }
            _ => {
                return Err("give at most one of bulk_ratio, d and incompressible".into());
            }
        };
        Ok(Material {
            law: model,
            compressibility,
        })
    }
}

impl From<Material> for MaterialJson {
    fn from(material: Material) -> MaterialJson {
        let none = Stated {
            bulk_ratio: None,
            d: None,
            incompressible: None,
        };
        let stated = match material.compressibility {
            Compressibility::Incompressible => Stated {
                incompressible: Some(true),
                ..none
            },
            Compressibility::BulkRatio(r) => Stated {
                bulk_ratio: Some(r),
                ..none
            },
            Compressibility::D(d) => Stated { d: Some(d), ..none },
        };
        MaterialJson::join(material.law, stated)
    }
}

impl Serialize for Material {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        MaterialJson::from(self.clone()).serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for Material {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let json = MaterialJson::deserialize(deserializer)?;
        Material::try_from(json).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Material, String> {
        serde_json::from_str(text).map_err(|e| e.to_string())
    }

    #[test]
    fn compressibility_is_stated_one_way_or_defaults_to_abaqus_explicit() {
        let m = read(r#"{"model": "arruda_boyce", "mu_mpa": 0.317, "lambda_m": 2.3}"#).unwrap();
        assert_eq!(m, Material::reference_balloon());
        assert_eq!(m.compressibility, Compressibility::BulkRatio(20.0));
        let m = read(r#"{"model": "neo_hookean", "mu_mpa": 1.3, "bulk_ratio": 20}"#).unwrap();
        assert_eq!(m, Material::reference_patch());
        let m = read(r#"{"model": "neo_hookean", "mu_mpa": 1, "incompressible": true}"#).unwrap();
        assert_eq!(m.compressibility, Compressibility::Incompressible);
        let m = read(r#"{"model": "neo_hookean", "mu_mpa": 1, "d": 0.1}"#).unwrap();
        assert_eq!(m.compressibility, Compressibility::D(0.1));
        let both = read(r#"{"model": "neo_hookean", "mu_mpa": 1, "d": 0.1, "bulk_ratio": 5}"#);
        assert!(both.unwrap_err().contains("at most one"));
        let no = read(r#"{"model": "neo_hookean", "mu_mpa": 1, "incompressible": false}"#);
        assert!(no.unwrap_err().contains("bulk_ratio"));
        let unknown = read(r#"{"model": "neo_hookean", "mu_mpa": 1, "poisson": 0.4}"#);
        assert!(unknown.unwrap_err().contains("poisson"));
    }

    #[test]
    fn written_materials_state_their_compressibility_and_read_back() {
        for m in [
            Material::reference_balloon().with_compressibility(Compressibility::abaqus_explicit()),
            Material::incompressible(Law::Gent {
                mu_mpa: 0.3,
                jm: 40.0,
            }),
            Material::compressible(
                Law::Ogden {
                    mu_mpa: vec![0.5, 0.01],
                    alpha: vec![1.5, 5.0],
                },
                Compressibility::D(0.2),
            ),
        ] {
            let text = serde_json::to_string(&m).unwrap();
            assert!(
                ["bulk_ratio", "\"d\"", "incompressible"]
                    .iter()
                    .any(|k| text.contains(k)),
                "{text}"
            );
            assert_eq!(read(&text).unwrap(), m);
        }
    }
}
