//! The two STL mnemonic sets. Generators write SIMATIC spellings; a file in international
//! mnemonics translates them here (`language.md` §2, `diagnostics.md` Appendix A.5).

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mnemonic {
    Simatic,
    International,
}

impl Mnemonic {
    /// An operation, given in its SIMATIC spelling.
    pub(crate) fn op(self, simatic: &'static str) -> &'static str {
        if self == Mnemonic::Simatic {
            return simatic;
        }
        match simatic {
            "U" => "A",
            "UN" => "AN",
            "U(" => "A(",
            "UN(" => "AN(",
            "UW" => "AW",
            "UD" => "AD",
            "SI" => "SP",
            "SV" => "SE",
            "SE" => "SD",
            "SA" => "SF",
            "ZV" => "CU",
            "ZR" => "CD",
            "TAR" => "CAR",
            "TAD" => "CAD",
            "TAW" => "CAW",
            other => other,
        }
    }

    /// An address area, given in its SIMATIC spelling.
    pub(crate) fn area(self, simatic: &'static str) -> &'static str {
        if self == Mnemonic::Simatic {
            return simatic;
        }
        match simatic {
            "E" => "I",
            "EB" => "IB",
            "EW" => "IW",
            "ED" => "ID",
            "A" => "Q",
            "AB" => "QB",
            "AW" => "QW",
            "AD" => "QD",
            "PEW" => "PIW",
            "PAW" => "PQW",
            "Z" => "C",
            other => other,
        }
    }

    pub(crate) fn keyword(self) -> &'static str {
        match self {
            Mnemonic::Simatic => "simatic",
            Mnemonic::International => "international",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Mnemonic::*;

    #[test]
    fn se_is_the_false_friend() {
        assert_eq!(International.op("SE"), "SD");
        assert_eq!(International.op("SV"), "SE");
        assert_eq!(Simatic.op("SE"), "SE");
        assert_eq!(International.area("Z"), "C");
        assert_eq!(International.op("O"), "O");
    }
}
