INSERT INTO individual (run_id, id, generation, parent_id, reward, fitness, diversity, r_max, balls, steps,
                        presses, pickups, carry_steps, basket_releases)
VALUES (:run_id, :id, :generation, :parent_id, :reward, :fitness, :diversity, :r_max, :balls, :steps,
        :presses, :pickups, :carry_steps, :basket_releases)
