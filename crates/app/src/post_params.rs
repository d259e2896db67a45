//! The post-processor choice and format options that `mill` and `sole` share.

use crate::Error;
use oficina_post::{post_for, Format, LineNumbers, Numbers, PostDialect, PostOptions, Units};
use serde::Deserialize;

#[derive(Clone, Debug, Deserialize)]
#[serde(default)]
/// The post-processor and the program's number format.
pub struct PostParams {
    /// linuxcnc, grbl, sinumerik or legacy-2006.
    pub post: String,
    /// The machine handles M6 (grbl forks with a changer).
    pub allow_m6: bool,
    /// Decimals in numbers (the dialect's default when not given).
    pub precision: Option<u8>,
    /// Write the program in inches.
    pub inch: bool,
    /// Number blocks N10, N20, … (START:STEP, e.g. 10:10).
    pub line_numbers: Option<String>,
    /// Every word on every block instead of leaving out repeated modal words.
    pub no_modal: bool,
}

impl Default for PostParams {
    fn default() -> Self {
        PostParams {
            post: "linuxcnc".into(),
            allow_m6: false,
            precision: None,
            inch: false,
            line_numbers: None,
            no_modal: false,
        }
    }
}

impl PostParams {
    /// The program's extension for this post.
    pub fn extension(&self) -> &'static str {
        match self.post.to_ascii_lowercase().as_str() {
            "sinumerik" | "sinumerik-7m" => "mpf",
            _ => "ngc",
        }
    }

    /// The post's options and number format, or why these parameters are wrong.
    pub fn options(
        &self,
        title: &str,
        settings: Vec<(String, String)>,
    ) -> Result<(PostOptions, Format), Error> {
        let dialect: PostDialect = self
            .post
            .parse()
            .map_err(|e| Error(format!("--post {}: {e}", self.post)))?;
        let mut f = post_for(dialect).default_format();
        if let Some(p) = self.precision {
            if matches!(f.numbers, Numbers::Integer { .. }) {
                return Err(Error(format!(
                    "--precision: the {} post writes integer words",
                    self.post
                )));
            }
            f.numbers = Numbers::Decimal { places: p };
        }
        if self.inch {
            f.units = Units::Inch;
        }
        if let Some(s) = &self.line_numbers {
            let (a, b) = s.split_once(':').unwrap_or((s, "10"));
            let parse = |v: &str| {
                v.trim().parse::<u32>().map_err(|e| {
                    Error(format!(
                        "--line-numbers {s}: write START:STEP, e.g. 10:10: {e}"
                    ))
                })
            };
            f.line_numbers = Some(LineNumbers {
                start: parse(a)?,
                step: parse(b)?,
            });
        }
        if self.no_modal {
            f.modal = false;
        }
        post_for(dialect)
            .check_format(&f)
            .map_err(|e| Error(format!("--post {}: {e}", self.post)))?;
        Ok((
            PostOptions {
                dialect,
                allow_m6: self.allow_m6,
                title: title.into(),
                settings,
            },
            f,
        ))
    }
}
