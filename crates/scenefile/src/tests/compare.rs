//! Comparisons (`[compare]`): the labelled cells laid out on one sheet.

use super::*;
use crate::shade::Shading;

#[test]
fn comparisons_lay_out_labelled_cells() {
    let file = toml(
        "size = [40, 30]\n[primitive]\nshape = \"sphere\"\nslices = 8\nstacks = 4\n\
         [compare]\ntitle = \"T\"\ncolumns = 2\nlabel_size = 10\n\
         [[compare.variant]]\nlabel = \"flat\"\nshading = \"flat\"\n\
         [[compare.variant]]\nlabel = \"shiny\"\nmaterial = [{ index = 0, shininess = 500 }]\n\
         [[compare.variant]]\nlabel = \"third\"\n",
    )
    .unwrap();
    let loaded = file.resolve(&LoadOptions::default()).unwrap();
    let cmp = loaded.comparison.unwrap();
    assert_eq!(cmp.variants.len(), 3);
    assert_eq!(cmp.variants[0].settings.shading, Some(Shading::Flat));
    assert_eq!(
        cmp.variants[1].settings.materials.as_ref().unwrap()[0].shininess,
        500.0
    );
    assert_eq!(cmp.variants[2].settings, loaded.settings);
    // Two columns, two rows of 30 + 18 px (label strip), a 23 px title strip.
    let red = [200u8, 0, 0].repeat(40 * 30);
    let img = compose(&cmp, (40, 30), &[red.clone(), red.clone(), red]);
    assert_eq!((img.width, img.height), (80, 23 + 2 * (30 + 18)));
    let px = |x: u32, y: u32| {
        let i = ((y * img.width + x) * 3) as usize;
        [img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]]
    };
    assert_eq!(px(5, 23 + 5), [200, 0, 0]);
    assert_eq!(px(45, 23 + 48 + 5), [32, 32, 36], "no fourth cell");
    // Labels are drawn in the strips: some light pixels under each of the three cells.
    for (x0, y0) in [(0, 23 + 30), (40, 23 + 30), (0, 23 + 48 + 30)] {
        let lit = (x0..x0 + 40)
            .flat_map(|x| (y0..y0 + 18).map(move |y| (x, y)))
            .filter(|&(x, y)| px(x, y)[0] > 150)
            .count();
        assert!(lit > 5, "label at {x0},{y0}: {lit}");
    }
    let (rendered, _) = cmp.render(
        &crate::render::PreparedScene::new(loaded.scene),
        &loaded.view,
    );
    assert_eq!((rendered.width, rendered.height), (img.width, img.height));
}
