//! The thread charts of the formats that store a palette index instead of a colour: Brother's
//! 64 PEC threads and Janome's 78 JEF threads (index 0 of each is unused; JEF uses it for a
//! stop). The colours are the published thread charts as pyembroidery and Embroidermodder
//! list them. A thread is written as the nearest chart colour by the "red mean" weighted RGB
//! distance (compuphase.com/cmetric.htm), the metric pyembroidery uses, so both pick the
//! same index.

/// A chart: index → (RGB, name); `None` where the index holds no thread.
pub(super) type Chart = [Option<([u8; 3], &'static str)>];

/// Brother's PEC chart, indices 1..=64.
pub(super) const PEC_THREADS: [Option<([u8; 3], &str)>; 65] = [
    None,
    Some(([14, 31, 124], "Prussian Blue")),
    Some(([10, 85, 163], "Blue")),
    Some(([0, 135, 119], "Teal Green")),
    Some(([75, 107, 175], "Cornflower Blue")),
    Some(([237, 23, 31], "Red")),
    Some(([209, 92, 0], "Reddish Brown")),
    Some(([145, 54, 151], "Magenta")),
    Some(([228, 154, 203], "Light Lilac")),
    Some(([145, 95, 172], "Lilac")),
    Some(([158, 214, 125], "Mint Green")),
    Some(([232, 169, 0], "Deep Gold")),
    Some(([254, 186, 53], "Orange")),
    Some(([255, 255, 0], "Yellow")),
    Some(([112, 188, 31], "Lime Green")),
    Some(([186, 152, 0], "Brass")),
    Some(([168, 168, 168], "Silver")),
    Some(([125, 111, 0], "Russet Brown")),
    Some(([255, 255, 179], "Cream Brown")),
    Some(([79, 85, 86], "Pewter")),
    Some(([0, 0, 0], "Black")),
    Some(([11, 61, 145], "Ultramarine")),
    Some(([119, 1, 118], "Royal Purple")),
    Some(([41, 49, 51], "Dark Gray")),
    Some(([42, 19, 1], "Dark Brown")),
    Some(([246, 74, 138], "Deep Rose")),
    Some(([178, 118, 36], "Light Brown")),
    Some(([252, 187, 197], "Salmon Pink")),
    Some(([254, 55, 15], "Vermilion")),
    Some(([240, 240, 240], "White")),
    Some(([106, 28, 138], "Violet")),
    Some(([168, 221, 196], "Seacrest")),
    Some(([37, 132, 187], "Sky Blue")),
    Some(([254, 179, 67], "Pumpkin")),
    Some(([255, 243, 107], "Cream Yellow")),
    Some(([208, 166, 96], "Khaki")),
    Some(([209, 84, 0], "Clay Brown")),
    Some(([102, 186, 73], "Leaf Green")),
    Some(([19, 74, 70], "Peacock Blue")),
    Some(([135, 135, 135], "Gray")),
    Some(([216, 204, 198], "Warm Gray")),
    Some(([67, 86, 7], "Dark Olive")),
    Some(([253, 217, 222], "Flesh Pink")),
    Some(([249, 147, 188], "Pink")),
    Some(([0, 56, 34], "Deep Green")),
    Some(([178, 175, 212], "Lavender")),
    Some(([104, 106, 176], "Wisteria Violet")),
    Some(([239, 227, 185], "Beige")),
    Some(([247, 56, 102], "Carmine")),
    Some(([181, 75, 100], "Amber Red")),
    Some(([19, 43, 26], "Olive Green")),
    Some(([199, 1, 86], "Dark Fuchsia")),
    Some(([254, 158, 50], "Tangerine")),
    Some(([168, 222, 235], "Light Blue")),
    Some(([0, 103, 62], "Emerald Green")),
    Some(([78, 41, 144], "Purple")),
    Some(([47, 126, 32], "Moss Green")),
    Some(([255, 204, 204], "Flesh Pink")),
    Some(([255, 217, 17], "Harvest Gold")),
    Some(([9, 91, 166], "Electric Blue")),
    Some(([240, 249, 112], "Lemon Yellow")),
    Some(([227, 243, 91], "Fresh Green")),
    Some(([255, 153, 0], "Orange")),
    Some(([255, 240, 141], "Cream Yellow")),
    Some(([255, 200, 200], "Applique")),
];

/// Janome's JEF chart, indices 1..=78.
pub(super) const JEF_THREADS: [Option<([u8; 3], &str)>; 79] = [
    None,
    Some(([0, 0, 0], "Black")),
    Some(([255, 255, 255], "White")),
    Some(([255, 255, 23], "Yellow")),
    Some(([255, 102, 0], "Orange")),
    Some(([47, 89, 51], "Olive Green")),
    Some(([35, 115, 54], "Green")),
    Some(([101, 194, 200], "Sky")),
    Some(([171, 90, 150], "Purple")),
    Some(([246, 105, 160], "Pink")),
    Some(([255, 0, 0], "Red")),
    Some(([177, 112, 78], "Brown")),
    Some(([11, 47, 132], "Blue")),
    Some(([228, 195, 93], "Gold")),
    Some(([72, 26, 5], "Dark Brown")),
    Some(([172, 156, 199], "Pale Violet")),
    Some(([252, 242, 148], "Pale Yellow")),
    Some(([249, 153, 183], "Pale Pink")),
    Some(([250, 179, 129], "Peach")),
    Some(([201, 164, 128], "Beige")),
    Some(([151, 5, 51], "Wine Red")),
    Some(([160, 184, 204], "Pale Sky")),
    Some(([127, 194, 28], "Yellow Green")),
    Some(([229, 229, 229], "Silver Gray")),
    Some(([136, 155, 155], "Gray")),
    Some(([152, 214, 189], "Pale Aqua")),
    Some(([178, 225, 227], "Baby Blue")),
    Some(([54, 139, 160], "Powder Blue")),
    Some(([79, 131, 171], "Bright Blue")),
    Some(([56, 106, 145], "Slate Blue")),
    Some(([7, 22, 80], "Navy Blue")),
    Some(([249, 153, 162], "Salmon Pink")),
    Some(([249, 103, 107], "Coral")),
    Some(([227, 49, 31], "Burnt Orange")),
    Some(([226, 161, 136], "Cinnamon")),
    Some(([181, 148, 116], "Umber")),
    Some(([228, 207, 153], "Blond")),
    Some(([255, 203, 0], "Sunflower")),
    Some(([225, 173, 212], "Orchid Pink")),
    Some(([195, 0, 126], "Peony Purple")),
    Some(([128, 0, 75], "Burgundy")),
    Some(([84, 5, 113], "Royal Purple")),
    Some(([177, 5, 37], "Cardinal Red")),
    Some(([202, 224, 192], "Opal Green")),
    Some(([137, 152, 86], "Moss Green")),
    Some(([92, 148, 26], "Meadow Green")),
    Some(([0, 49, 20], "Dark Green")),
    Some(([93, 174, 148], "Aquamarine")),
    Some(([76, 191, 143], "Emerald Green")),
    Some(([0, 119, 114], "Peacock Green")),
    Some(([89, 91, 97], "Dark Gray")),
    Some(([255, 255, 242], "Ivory White")),
    Some(([177, 88, 24], "Hazel")),
    Some(([203, 138, 7], "Toast")),
    Some(([152, 108, 128], "Salmon")),
    Some(([152, 105, 45], "Cocoa Brown")),
    Some(([77, 52, 25], "Sienna")),
    Some(([76, 51, 11], "Sepia")),
    Some(([51, 32, 10], "Dark Sepia")),
    Some(([82, 58, 151], "Violet Blue")),
    Some(([13, 33, 126], "Blue Ink")),
    Some(([30, 119, 172], "Sola Blue")),
    Some(([178, 221, 83], "Green Dust")),
    Some(([243, 54, 137], "Crimson")),
    Some(([222, 100, 158], "Floral Pink")),
    Some(([152, 65, 97], "Wine")),
    Some(([76, 86, 18], "Olive Drab")),
    Some(([76, 136, 31], "Meadow")),
    Some(([228, 222, 121], "Mustard")),
    Some(([203, 138, 26], "Yellow Ocher")),
    Some(([203, 162, 28], "Old Gold")),
    Some(([255, 152, 5], "Honey Dew")),
    Some(([252, 178, 87], "Tangerine")),
    Some(([255, 229, 5], "Canary Yellow")),
    Some(([240, 51, 31], "Vermilion")),
    Some(([26, 132, 45], "Bright Green")),
    Some(([56, 108, 174], "Ocean Blue")),
    Some(([227, 196, 180], "Beige Gray")),
    Some(([227, 172, 129], "Bamboo")),
];

/// The red-mean distance between two colours (integer form, as pyembroidery computes it).
pub(super) fn distance(a: [u8; 3], b: [u8; 3]) -> i64 {
    let (r1, g1, b1) = (a[0] as i64, a[1] as i64, a[2] as i64);
    let (r2, g2, b2) = (b[0] as i64, b[1] as i64, b[2] as i64);
    // round((r1 + r2) / 2) with halves to even, as Python's round does.
    let sum = r1 + r2;
    let mean = if sum % 4 == 1 { sum / 2 } else { (sum + 1) / 2 };
    let (r, g, b) = (r1 - r2, g1 - g2, b1 - b2);
    (((512 + mean) * r * r) >> 8) + 4 * g * g + (((767 - mean) * b * b) >> 8)
}

/// The index of the chart colour nearest `rgb`, skipping `None` entries and those `skip`
/// says; on a tie the later index wins (as pyembroidery). None when every entry is skipped.
pub(super) fn nearest(rgb: [u8; 3], chart: &Chart, skip: &dyn Fn(usize) -> bool) -> Option<usize> {
    let mut best: Option<(usize, i64)> = None;
    for (i, t) in chart.iter().enumerate() {
        let Some((c, _)) = t else { continue };
        if skip(i) {
            continue;
        }
        let d = distance(rgb, *c);
        if best.is_none_or(|(_, bd)| d <= bd) {
            best = Some((i, d));
        }
    }
    best.map(|(i, _)| i)
}

/// The thread at a chart index (wrapped into the chart as pyembroidery does), or None for an
/// empty entry.
pub(super) fn thread_at(chart: &Chart, index: usize) -> Option<crate::plan::Thread> {
    chart[index % chart.len()].map(|(rgb, name)| crate::plan::Thread {
        rgb,
        name: name.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chart_colours_are_their_own_nearest() {
        for (chart, n) in [(&PEC_THREADS[..], 65), (&JEF_THREADS[..], 79)] {
            assert_eq!(chart.len(), n);
            for (i, t) in chart.iter().enumerate() {
                if let Some((rgb, _)) = t {
                    let j = nearest(*rgb, chart, &|_| false).unwrap();
                    assert_eq!(chart[j].unwrap().0, *rgb, "index {i}");
                }
            }
        }
        // Pure red is Brother's Red (5) and Janome's Red (10).
        assert_eq!(nearest([255, 0, 0], &PEC_THREADS, &|_| false), Some(5));
        assert_eq!(nearest([255, 0, 0], &JEF_THREADS, &|_| false), Some(10));
    }
}
