//! `prism compare TEST REF [--json]`.

use crate::compare::compare;
use crate::io::read_image;
use std::path::Path;

pub fn run(test: &Path, reference: &Path, json: bool) -> anyhow::Result<()> {
    let a = read_image(test)?;
    let b = read_image(reference)?;
    let m = compare(&a, &b)?;
    if json {
        println!(
            "{{\"rmse\": {}, \"relmse\": {}, \"mae\": {}, \"mean_test\": [{}, {}, {}], \"mean_reference\": [{}, {}, {}]}}",
            m.rmse,
            m.relmse,
            m.mae,
            m.mean_test[0],
            m.mean_test[1],
            m.mean_test[2],
            m.mean_reference[0],
            m.mean_reference[1],
            m.mean_reference[2]
        );
    } else {
        println!("RMSE    {:.6}", m.rmse);
        println!("relMSE  {:.6}", m.relmse);
        println!("MAE     {:.6}", m.mae);
        println!(
            "mean    ({:.6}, {:.6}, {:.6})  reference ({:.6}, {:.6}, {:.6})",
            m.mean_test[0],
            m.mean_test[1],
            m.mean_test[2],
            m.mean_reference[0],
            m.mean_reference[1],
            m.mean_reference[2]
        );
    }
    Ok(())
}
