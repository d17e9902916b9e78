SELECT max(best_reward) FROM generation
